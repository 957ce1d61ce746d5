"""``make bench``: runs every benchmark and writes its figures to bench/out/.

``python -m bench.run [names...]`` runs only the named ones (interfaces, lp, nlp, step2_large, wall_family, sweep, capacity_curve, dem, dem_models, engines, dem_family).
"""
from __future__ import annotations

import importlib
import sys

BENCHES = ["interfaces", "lp", "nlp", "step2_large", "wall_family", "sweep", "capacity_curve", "dem", "dem_models", "engines",
           "dem_family"]


def main(argv=None) -> int:
    names = (argv if argv is not None else sys.argv[1:]) or BENCHES
    for name in names:
        if name not in BENCHES:
            print(f"unknown benchmark {name!r} (one of {', '.join(BENCHES)})", file=sys.stderr)
            return 2
        print(f"== bench {name}", flush=True)
        importlib.import_module(f"bench.{name}_bench").main()
    return 0


if __name__ == "__main__":
    sys.exit(main())
