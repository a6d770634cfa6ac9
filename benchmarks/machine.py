"""The machine a benchmark ran on, as lines for the console and ``#`` lines in CSV files."""

from __future__ import annotations

import os
import platform
import subprocess

import numba
import numpy as np


def describe() -> list[str]:
    """CPU, core and thread counts, numba's threading layer, versions, load average."""
    from fluidsim_envs.physics import Craft, Simulator

    # a parallel call first, so that numba has picked its threading layer
    Simulator(Craft(name="probe", mass_kg=1.0, inertia_kgm2=(1, 1, 1)), parallel=True).step()
    try:
        lscpu = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        model = next(
            (
                ln.split(":", 1)[1].strip()
                for ln in lscpu.splitlines()
                if ln.startswith("Model name")
            ),
            "",
        )
    except OSError:
        model = ""
    return [
        f"cpu: {model or platform.processor() or 'unknown'} ({platform.machine()})",
        f"os.cpu_count: {os.cpu_count()}, numba threads: {numba.config.NUMBA_NUM_THREADS}, "
        f"threading layer: {numba.threading_layer()}",
        f"python {platform.python_version()}, numba {numba.__version__}, "
        f"numpy {np.__version__}, {platform.system()} {platform.release()}",
        "load average at start: " + ", ".join(f"{x:.2f}" for x in os.getloadavg()),
    ]
