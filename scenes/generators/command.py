"""``limit build KIND ... -o SCENE.json``: the command line of :mod:`scenes.generators`."""
from __future__ import annotations


def add_arguments(p) -> None:
    p.add_argument("kind")
    p.add_argument("-o", "--output", required=True, metavar="SCENE.json")


def run(args) -> int:
    raise NotImplementedError("limit build")
