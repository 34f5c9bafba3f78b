"""One compute thread for numpy's BLAS and for torch.

The networks here are small (batch 128 x 128 units): a second BLAS thread buys nothing, and
OpenBLAS's worker threads, spinning while the environment steps or while another process
holds the other core, made updates up to 20x slower in measurements on 2-core machines.
"""

from __future__ import annotations

import ctypes
import glob
import os

_SETTERS = ("scipy_openblas_set_num_threads64_", "scipy_openblas_set_num_threads",
            "openblas_set_num_threads64_", "openblas_set_num_threads")


def _openblas_libraries() -> list[str]:
    paths = set()
    try:
        with open("/proc/self/maps") as f:
            for line in f:
                p = line.split()[-1] if line.rstrip().endswith(".so") or ".so." in line else ""
                if "openblas" in os.path.basename(p).lower():
                    paths.add(p)
    except OSError:
        pass
    import numpy

    here = os.path.dirname(numpy.__file__)
    paths.update(glob.glob(os.path.join(here, "..", "numpy.libs", "*openblas*")))
    paths.update(glob.glob(os.path.join(here, ".libs", "*openblas*")))
    return sorted(paths)


def limit_threads(n: int = 1) -> bool:
    """Set numpy's OpenBLAS and torch (if imported) to ``n`` threads; True if OpenBLAS was found."""
    import sys

    if "torch" in sys.modules:
        sys.modules["torch"].set_num_threads(n)
    done = False
    for path in _openblas_libraries():
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for name in _SETTERS:
            fn = getattr(lib, name, None)
            if fn is not None:
                fn(ctypes.c_int(n))
                done = True
                break
    return done
