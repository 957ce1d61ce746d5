"""How the host starts YADE: its executable and the address-space setting its runs need."""
from __future__ import annotations

import os
import shutil
import subprocess


def find_yade(yade: str | None) -> str | None:
    """Path of the YADE executable: ``yade`` (a name looked up on PATH or a path),
    else $DEM_YADE, else ``yade`` on PATH; None when there is none."""
    name = yade or os.environ.get("DEM_YADE") or "yade"
    if os.sep in name:
        return name if os.path.isfile(name) and os.access(name, os.X_OK) else None
    return shutil.which(name)


_NO_ASLR: list[str] | None = None


def no_aslr_prefix() -> list[str]:
    """Command prefix that starts YADE with address-space randomization off
    (``setarch <machine> -R``), or [] where the kernel or a sandbox refuses it.

    YADE builds each Polyhedra's surface with CGAL, and the order of its vertices and
    the triangulation of coplanar faces follow heap addresses, which shift with the process's
    environment (dem_validation.runner.engine_env fixes it) and with address randomization (this
    prefix turns it off): with both fixed, a scene gets the same surfaces in every run."""
    global _NO_ASLR
    if _NO_ASLR is None:
        exe = shutil.which("setarch")
        prefix = [exe, os.uname().machine, "-R"] if exe else []
        if prefix:
            try:
                ok = subprocess.run(prefix + ["true"], stdin=subprocess.DEVNULL, capture_output=True,
                                    timeout=30).returncode == 0
            except (OSError, subprocess.TimeoutExpired):
                ok = False
            prefix = prefix if ok else []
        _NO_ASLR = prefix
    return _NO_ASLR
