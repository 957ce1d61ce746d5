"""``limit import FILE... -o SCENE.json``: the command line of :mod:`scenes.importers`."""
from __future__ import annotations


def add_arguments(p) -> None:
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("-o", "--output", required=True, metavar="SCENE.json")


def run(args) -> int:
    raise NotImplementedError("limit import")
