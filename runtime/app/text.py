"""Text the application shows: names from a scene file made safe, durations and sizes in words.

Why: scene and body names are the user's text.  Printed raw, a name holding terminal escape codes
recolours or rewrites the user's terminal (and a newline breaks the one-line messages); used as
a folder name, ``../x`` or ``a/b`` would write somewhere else.  Matplotlib's mathtext is turned
off where names are drawn (runtime/app/plotting.py), so a ``$`` in a name is just a dollar.
"""

from __future__ import annotations

import re

__all__ = ["folder_name", "human_bytes", "human_seconds", "terminal_safe"]


def _escape(char: str) -> str:
    code = ord(char)
    if code < 0x100:
        return f"\\x{code:02x}"
    return f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}"


def terminal_safe(text: str) -> str:
    """``text`` with every character that is not printable (control and format characters such
    as ESC, newline, carriage return, bidirectional overrides) written as a ``\\xNN``-style
    escape, as ``repr`` would; printable text, accents and all, is kept as it is."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else _escape(c) for c in text)


_UNSAFE = re.compile(r"[^A-Za-z0-9._-]+")


def folder_name(name: str, fallback: str = "scene") -> str:
    """A file-system-safe single path component for ``name``: letters, digits, ``. _ -``, runs
    of anything else as one ``_``, no leading dot (no hidden folders, no ``..``)."""
    safe = _UNSAFE.sub("_", name).lstrip("._").rstrip("_")
    return safe or fallback


def human_seconds(seconds: float) -> str:
    """'42 s', '7.5 min', '3.2 h', '12 days', '3.1e+04 years' (3 significant digits)."""
    for unit, size in (("years", 365.25 * 86400), ("days", 86400), ("h", 3600), ("min", 60)):
        if seconds >= 2 * size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.3g} s"


def human_bytes(size: float) -> str:
    """'350 kB', '2.1 GB', '4.4e+05 GB' (decimal units, 3 significant digits)."""
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if size >= scale:
            return f"{size / scale:.3g} {unit}"
    return f"{size:.0f} B"
