"""``make bench``: runs every benchmark module and writes its figures to bench/out/."""
from __future__ import annotations

import sys

from . import interfaces_bench


def main() -> int:
    interfaces_bench.main()
    return 0


if __name__ == "__main__":
    sys.exit(main())
