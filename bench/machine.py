"""The machine a benchmark ran on, for the reports that quote timings (one place for all)."""

from __future__ import annotations

import os
import platform
import re
import subprocess


def cpu() -> str:
    """'<CPU model>, <n> cores' from lscpu (physical cores), else what platform knows."""
    model, cores = platform.processor() or platform.machine() or "unknown CPU", os.cpu_count()
    try:
        lscpu = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
        fields = dict(re.findall(r"^([^:\n]+):\s*(.*)$", lscpu, flags=re.M))
        model = fields.get("Model name", model)
        cores = int(fields.get("Core(s) per socket", 0)) * int(fields.get("Socket(s)", 0)) or cores
    except (OSError, subprocess.CalledProcessError, ValueError):
        pass
    return f"{model}, {cores} cores"
