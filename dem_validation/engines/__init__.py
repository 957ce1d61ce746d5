"""The DEM engines behind one interface, and their registry.

An engine runs a loaded scene with checked knobs in its own process and returns a
:class:`~dem_validation.engines.result.DemResult`. Each engine is one subpackage:
its host-side adapter (``__init__.py``, with ``ENGINE``) and the scripts that run in
the engine's process (``side_files``, copied beside the job by
:mod:`dem_validation.runner`; they import one another by plain module name). A new
engine is a new subpackage and one line in :data:`MODULES`.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol, runtime_checkable

from .result import DemResult, Status

#: engine name -> the module that defines it (as its ``ENGINE``)
MODULES = {"yade": "dem_validation.engines.yade", "lmgc90": "dem_validation.engines.lmgc90"}
#: the engine of a ``dem`` dict without an ``engine`` key, and of ``run_scene`` by default
DEFAULT = "yade"

__all__ = ["DEFAULT", "DemResult", "Engine", "MODULES", "Models", "Status", "get", "help_text", "names",
           "of_result"]


@dataclass(frozen=True)
class Models:
    """What an engine's block model carries besides rigid blocks on dry Coulomb joints."""

    ties: bool = False  # tie rods
    bonds: bool = False  # joints with cohesion or tensile strength
    compound: bool = True  # blocks made of several convex parts


@runtime_checkable
class Engine(Protocol):
    """One DEM engine, as the host sees it."""

    name: str  # the registry key (``--engine``, ``run_scene(engine=...)``)
    label: str  # the name in messages
    description: str  # one phrase for ``--engine``'s help
    rigid: bool  # rigid contacts: one run of trials from rest (its history's stable trials are rigid-block points)
    knob_table: dict  # knob -> (default, meaning)
    side_dir: Path  # where the side files are
    side_files: tuple  # the modules that run in the engine's process
    entry: str  # the entry script among them

    def knobs(self, given: dict, contact: str = "vertex") -> dict:
        """The defaults updated with ``given``; ValueError naming a bad knob."""

    def models(self, contact: str = "vertex") -> Models:
        """What the block model ``contact`` carries."""

    def executable(self, given: str | None) -> str:
        """The program that runs the entry script (``given``: the user's choice);
        LookupError with the reason when there is none."""

    def command(self, exe: str, entry: str) -> list:
        """The command line that runs ``entry`` on ``job.json`` in the work directory."""

    def run_facts(self) -> dict:
        """Keys the runner adds to every result the engine side writes."""

    def run(self, scene, p: dict, *, timeout_s=None, progress=None, keep_dir=False, interfaces=None,
            cpu_limit_s=None, hint=None, executable=None, contact="vertex") -> DemResult:
        """The pushover of a loaded scene with checked knobs ``p``; every fault is a failed result."""

    def collapse_line(self, dem: dict) -> str:
        """The summary line of a ``dem`` dict that collapsed at an alpha."""


def names() -> tuple:
    """The known engines, the default first."""
    return tuple(MODULES)


def get(name: str) -> Engine:
    """The engine called ``name``; ValueError naming the known ones."""
    if name not in MODULES:
        raise ValueError(f"engine: expected one of {', '.join(MODULES)}, got {name!r}")
    return importlib.import_module(MODULES[name]).ENGINE


def of_result(dem: dict) -> Engine:
    """The engine that made a ``dem`` dict (its ``engine`` key, else :data:`DEFAULT`)."""
    return get(dem.get("engine") or DEFAULT)


def help_text() -> str:
    """Every engine and what it is, for ``--engine``'s help."""
    return "; ".join(f"{n}: {get(n).description}" + (" (default)" if n == DEFAULT else "") for n in MODULES)
