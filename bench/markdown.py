"""Markdown sections of the benchmark READMEs: each benchmark owns one "## " section."""

from __future__ import annotations

import re
from pathlib import Path


def replace_section(path: Path, heading: str, body: str, before: str | None = None) -> None:
    """Replace the `heading` section of a Markdown file (up to the next "## "), or add it before
    the `before` section (or at the end): the other sections, owned by others, stay as they are."""
    text = path.read_text() if path.exists() else ""
    body = body.rstrip("\n") + "\n\n"
    pattern = re.compile(rf"^{re.escape(heading)}\n.*?(?=^## |\Z)", flags=re.M | re.S)
    old = pattern.search(text)
    if old:
        text = text[: old.start()] + body + text[old.end() :]
    elif before and (nxt := re.search(rf"^{re.escape(before)}\n", text, flags=re.M)):
        text = text[: nxt.start()] + body + text[nxt.start() :]
    else:
        text = text.rstrip("\n") + "\n\n" + body
    path.write_text(text.rstrip("\n") + "\n")
