"""The route thresholds, time budgets and check tolerances of the analysis, in one place.

:class:`Settings` is a frozen dataclass; :data:`DEFAULT` holds the values the analysis uses
unless told otherwise. Each field's metadata gives its group, unit and what it decides
(docs/settings.md lists them; ``limit settings`` prints them). A run takes its settings from
``limit.Options(settings=...)`` (a :class:`Settings` or a mapping of the fields to change) or
from ``limit solve --set NAME=VALUE``; the code reads them from the assembled problem
(:func:`of`), never from module globals. The algorithms' internal constants (penalty
schedules, relaxations, snap thresholds) stay in their modules.

A leaf module: it imports nothing from :mod:`limit`.
"""
import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field

#: the groups, in the order they are listed
GROUPS = {"route": "problem sizes that choose a route or a solver",
          "budget": "time budgets",
          "tolerance": "tolerances of the a posteriori checks and of the choices between answers"}


def _s(default, group: str, unit: str, doc: str):
    return field(default=default, metadata={"group": group, "unit": unit, "doc": doc})


@dataclass(frozen=True)
class Settings:
    """Route thresholds, time budgets and tolerances (see each field's ``metadata``)."""

    # -- route: problem sizes ---------------------------------------------------------------
    lp_ipm_min_dof: int = _s(
        3000, "route", "block unknowns",
        "step 1's solver 'auto' takes the structured interior point method (ipm) from this many on, "
        "Clarabel below (make bench: equally fast near 1,000 2D blocks; ipm 2.8x faster at 30,000 unknowns)")
    slsqp_max_vars: int = _s(
        250, "route", "NLP unknowns",
        "step 2's solver 'auto' runs SLSQP up to this many, the successive LP above")
    highs_max_vars: int = _s(
        3000, "route", "NLP unknowns",
        "step 2's sparse LPs (phase 1, successive LP, DEM start) use HiGHS up to this many, Clarabel above")
    many_restarts_max_vars: int = _s(
        5000, "route", "NLP unknowns",
        "up to this many, step 2 makes the larger number of random restarts "
        "(limit.solve.nlp_starts.RANDOM_RESTARTS), above the smaller")
    large_min_free: int = _s(
        200, "route", "free blocks",
        "step 2's solver 'auto' takes only the large-scale route (iterative LP, limit.solve.step2_large) "
        "from this many on; below, the successive LP's many starts found lower alphas (68-126-block "
        "walls: 3-4 % lower); at 300 blocks it stops at its time budget with a local point")
    also_iterative: bool = _s(
        True, "route", "-",
        "below large_min_free, step 2's solver 'auto' runs the large-scale route too, before the "
        "successive LP, and keeps its verified alpha where lower by more than lower_by (70-stone Fig. 3 "
        "wall: 0.520808 against the successive LP's 0.570752; docs/performance.md, 'The wall family')")
    one_round_min_free: int = _s(
        2000, "route", "free blocks",
        "from this many on, the large-scale route runs only as many starts as there are workers, "
        "with relaxation OMEGA_LARGE (and warm-started LPs in 2D)")
    very_large_min_free: int = _s(
        5000, "route", "free blocks",
        "from this many on (2D), the large-scale route snaps at lower residuals, 'ratio' rule first, "
        "from the starts at 0.5 mu and 0.4 mu, and its starts stop once one has verified")
    prox_min_free: int = _s(
        5000, "route", "free blocks",
        "from this many on (2D), each LP of the large-scale route is the proximal QP (step2_large.PROX)")
    direction_starts_deg: int = _s(
        5, "route", "deg",
        "3D scenes loaded by body forces, below large_min_free free blocks: step 2 also runs with the "
        "live load turned by +- this about the vertical and tries those collapse states as starts "
        "(limit.analysis); 0: off. On the 13 3D catalog scenes it lowers one, Fig. 6, from 0.3608 to a "
        "verified 0.2195 (9/41), at 2-3.5 times step 2's time (docs/performance.md)")
    friction_starts: bool = _s(
        True, "route", "on/off",
        "below large_min_free free blocks, where the LP mechanism neither slides nor twists: step 2 also "
        "runs (method nlp) with every friction coefficient "
        "and cohesion scaled by the factors of limit.solve.nlp_starts.FRICTION_FACTORS (0.5, 0.25) and tries "
        "those collapse states as starts (limit.analysis): sliding-first states that step 2 at full "
        "friction does not reach. It lowers the out-of-plane wall from t/H = 0.19048 to a verified "
        "0.181726, the MILP's best state (docs/performance.md)")
    mirror_starts: bool = _s(
        True, "route", "on/off",
        "3D scenes loaded by body forces, below large_min_free free blocks, that a vertical mirror "
        "across the live load maps onto themselves (limit.model.reversal_mirror): step 2 also runs with "
        "the live load reversed and tries that collapse state, reflected, as a start (limit.analysis). "
        "It lowers the catalog's wall-3x3-3d loaded out of its plane (turned by 90 deg) from the LP's "
        "0.5 to a verified 6/13, the state step 2 reaches under the reversed load (docs/performance.md)")
    global_max_blocks: int = _s(
        30, "route", "free blocks",
        "the mixed-integer global check (--global) runs for scenes up to this many; above it is skipped")
    curve_steps: int = _s(
        20, "route", "steps",
        "equal steps of the control displacement of the incremental capacity curve "
        "(limit.incremental_curve; sliding and mixed mechanisms): the first-order error "
        "against the kinematic-chain follower on portal-2d halves from 20 to 40 steps (2.6e-4 to 1.1e-4 "
        "in alpha) at twice the time (tests/test_incremental_curve.py)")

    # -- budget: wall-clock limits -----------------------------------------------------------
    nlp_time_budget: float = _s(
        120.0, "budget", "s",
        "step 2's budget: no restart begins after it once a verified point is in hand "
        "(--nlp-time-budget overrides it)")
    hard_factor: float = _s(
        5.0, "budget", "budgets",
        "without a verified point step 2 goes on up to this many budgets, then stops for good")
    global_time_limit: float = _s(
        120.0, "budget", "s",
        "wall-clock limit of the global MILP; at the limit its best point so far counts "
        "(--global-time-limit overrides it)")
    curve_time_budget: float = _s(
        60.0, "budget", "s",
        "the incremental capacity curve starts no step after this; a curve that has not reached "
        "alpha = 0 by then has no d0 and says why")

    # -- tolerance: a posteriori checks (dimensionless, limit.solve.verify) ------------------
    tol_eq: float = _s(
        1e-6, "tolerance", "scaled force",
        "equilibrium residual, whole and per block (relative to its own load), of every answer")
    tol_yield: float = _s(
        1e-6, "tolerance", "scaled force",
        "yield violation max(Yh xh - kh) of every answer (rows of unit largest coefficient)")
    tol_kin: float = _s(
        1e-6, "tolerance", "relative",
        "compatibility (relative to the largest term), negative multipliers and normalisation "
        "|fL . u - 1| of every mechanism")
    tol_gap: float = _s(
        1e-6, "tolerance", "relative to max(1, |alpha|)",
        "the LP's duality gap; how far a frictional alpha may lie above the LP's; "
        "an alpha below -tol_gap is a collapse under the dead load")
    tol_comp: float = _s(
        1e-6, "tolerance", "alpha units: sum |lam s| / max(1, |alpha|)",
        "complementarity residual a frictional point may have to pass the check (TOL_COMP)")
    sla_comp_target: float = _s(
        1e-7, "tolerance", "alpha units: lam . s / max(1, alpha)",
        "the successive LP stops raising its penalty below this: a stopping target kept under "
        "tol_comp (ten times) so that its point passes the check; not a check itself")
    lower_by: float = _s(
        1e-9, "tolerance", "relative",
        "a verified alpha from another route (large-scale, global MILP, DEM start) replaces step 2's "
        "only when lower by more than this")

    def __post_init__(self):
        for f in dataclasses.fields(self):
            object.__setattr__(self, f.name, _checked(f, getattr(self, f.name)))

    def changed(self) -> dict:
        """{name: value} of the fields that differ from the defaults (a cache key's part)."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)
                if getattr(self, f.name) != f.default}

    def replace(self, changes: "Mapping | None" = None, **kw) -> "Settings":
        """These settings with ``changes`` (and keywords) applied; ValueError names an unknown
        key (listing the valid ones) or a value of the wrong type."""
        changes = {**(changes or {}), **kw}
        valid = names()
        for k in changes:
            if k not in valid:
                raise ValueError(f"unknown setting {k!r}; valid: {', '.join(valid)}")
        return dataclasses.replace(self, **changes)


def _checked(f: dataclasses.Field, v):
    """``v`` as field ``f``'s type, or ValueError naming the field."""
    kind = f.type
    ok = (isinstance(v, bool) if kind is bool else
          isinstance(v, int) and not isinstance(v, bool) if kind is int else
          isinstance(v, (int, float)) and not isinstance(v, bool))
    if not ok:
        raise ValueError(f"setting {f.name!r}: expected {kind.__name__}, got {v!r} ({type(v).__name__})")
    if kind is float:
        v = float(v)
        if not v > 0:
            raise ValueError(f"setting {f.name!r}: must be > 0, got {v!r}")
    if kind is int and v < 0:
        raise ValueError(f"setting {f.name!r}: must be >= 0, got {v!r}")
    return v


DEFAULT = Settings()


def names() -> tuple:
    """Every setting's name, in the dataclass's order."""
    return tuple(f.name for f in dataclasses.fields(Settings))


def resolve(given) -> Settings:
    """A :class:`Settings` from ``given``: None (the defaults), a Settings, or a mapping of the
    fields to change from the defaults."""
    if given is None:
        return DEFAULT
    if isinstance(given, Settings):
        return given
    if isinstance(given, Mapping):
        return DEFAULT.replace(given)
    raise ValueError(f"settings: a limit.settings.Settings or a mapping of its fields, not {type(given).__name__}")


def parse(item: str) -> tuple:
    """(name, value) of a command-line ``NAME=VALUE``, the value read as the field's type
    (bool: true/false, yes/no, 1/0); ValueError names the key."""
    key, sep, text = item.partition("=")
    key, text = key.strip(), text.strip()
    if not sep or not key:
        raise ValueError(f"--set {item!r}: expected NAME=VALUE")
    fields = {f.name: f for f in dataclasses.fields(Settings)}
    if key not in fields:
        raise ValueError(f"--set {item!r}: unknown setting {key!r}; valid: {', '.join(fields)}")
    kind = fields[key].type
    try:
        if kind is bool:
            low = text.lower()
            if low not in ("true", "false", "yes", "no", "1", "0"):
                raise ValueError
            value = low in ("true", "yes", "1")
        else:
            value = kind(text)
    except ValueError:
        raise ValueError(f"--set {item!r}: setting {key!r} takes {kind.__name__}, got {text!r}") from None
    return key, value


def of(P) -> Settings:
    """The settings in use for an assembled problem P (its options'), else the defaults."""
    return getattr(getattr(P, "options", None), "settings", None) or DEFAULT


def table() -> list[dict]:
    """One row per setting: name, group, type, default, unit, meaning (for docs and ``limit settings``)."""
    return [{"name": f.name, "group": f.metadata["group"], "type": f.type.__name__, "default": f.default,
             "unit": f.metadata["unit"], "doc": f.metadata["doc"]} for f in dataclasses.fields(Settings)]


def format_table() -> str:
    """The settings as text, by group."""
    lines = []
    for g, what in GROUPS.items():
        lines.append(f"{g}: {what}")
        for r in table():
            if r["group"] == g:
                lines.append(f"  {r['name']} = {r['default']!r} ({r['type']}, {r['unit']})")
                lines.append(f"      {r['doc']}")
    return "\n".join(lines)


def markdown_table() -> str:
    """The settings as the Markdown table of docs/settings.md."""
    rows = ["| name | group | default | unit | what it decides |", "| --- | --- | --- | --- | --- |"]
    esc = lambda t: str(t).replace("|", "\\|")  # noqa: E731
    rows += [f"| `{r['name']}` | {r['group']} | `{r['default']!r}` | {esc(r['unit'])} | {esc(r['doc'])} |"
             for r in table()]
    return "\n".join(rows)
