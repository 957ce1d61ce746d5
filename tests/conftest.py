import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# `limit solve` keeps its results in the repository's cache; the suite solves afresh (its subprocesses
# inherit this), and tests/test_cli.py checks the cache with a folder of its own
os.environ["LIMIT_NO_CACHE"] = "1"


@pytest.fixture
def write_scene(tmp_path):
    """Write a scene dict (or raw text) to a file and return its path."""
    counter = {"n": 0}

    def _write(content, name=None):
        counter["n"] += 1
        p = tmp_path / (name or f"scene{counter['n']}.json")
        p.write_text(content if isinstance(content, str) else json.dumps(content))
        return p

    return _write


def run_module(module, *args, timeout=600):
    """Run ``python -m module args`` in a subprocess; returns CompletedProcess (text)."""
    return subprocess.run([sys.executable, "-m", module, *map(str, args)], capture_output=True, text=True,
                          cwd=ROOT, timeout=timeout)
