"""The route thresholds, time budgets and check tolerances of the analysis, in one place.

:class:`Settings` is a frozen dataclass; :data:`DEFAULT` holds the values the analysis uses
unless told otherwise. Each field's metadata gives its group, unit and what it decides
(docs/settings.md lists them; ``limit settings`` prints them). A run takes its settings from
``limit.Options(settings=...)`` (a :class:`Settings` or a mapping of the fields to change) or
from ``limit solve --set NAME=VALUE``; the code reads them from the assembled problem
(:func:`of`), never from module globals. The large-scale route's tuned numbers (relaxation,
snap thresholds, starts) are settings too (group "large"); the other algorithms' internal
constants (penalty schedules, the interior point method's safeguards) and the large route's
structural choices (snap rules and backends, the dimensions a rule applies in) stay in their
modules.

A leaf module: it imports nothing from :mod:`limit`.
"""
import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field

#: the groups, in the order they are listed
GROUPS = {"route": "problem sizes that choose a route or a solver",
          "large": "step 2's large-scale route (limit.solve.step2_large): relaxation, snap thresholds "
                   "and starts, each chosen by the measurements in docs/performance.md, 'Step 2 at "
                   "scale: the measurements behind its constants'",
          "budget": "time budgets",
          "tolerance": "tolerances of the a posteriori checks and of the choices between answers"}


def _s(default, group: str, unit: str, doc: str, zero_ok: bool = False):
    """A field with its group, unit and meaning; a float must be > 0 (>= 0 with ``zero_ok``)."""
    return field(default=default, metadata={"group": group, "unit": unit, "doc": doc, "zero_ok": zero_ok})


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
        "with relaxation large_omega_one_round at most (and warm-started LPs in 2D)")
    very_large_min_free: int = _s(
        5000, "route", "free blocks",
        "from this many on (2D), the large-scale route snaps at lower residuals, 'ratio' rule first, "
        "from the starts at 0.5 mu and 0.4 mu, and its starts stop once one has verified")
    prox_min_free: int = _s(
        5000, "route", "free blocks",
        "from this many on (2D), each LP of the large-scale route is the proximal QP (large_prox)")
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

    # -- large: step 2's large-scale route ---------------------------------------------------
    large_omega_2d: float = _s(
        1.0, "large", "-",
        "relaxation of the iteration on the normal forces, N* <- N* + omega (N - N*), in 2D (halved "
        "down to large_omega_min whenever the complementarity residual has no new low for large_stall LPs)")
    large_omega_3d: float = _s(
        0.5, "large", "-",
        "the same in 3D, where omega = 1 oscillates")
    large_omega_one_round: float = _s(
        0.5, "large", "-",
        "the relaxation at most, from one_round_min_free free blocks on, where omega = 1 oscillates")
    large_omega_min: float = _s(
        0.125, "large", "-",
        "the smallest relaxation; a start with no new low for large_stall LPs there stops as stalled, so "
        "that its budget goes to the other starts")
    large_stall: int = _s(
        16, "large", "LPs",
        "LPs without a new low of the complementarity residual that halve the relaxation (wall family: "
        "with 8 a 626-block 2D wall's 0.25 mu start halves it to the floor and stops as stalled; with "
        "16 and large_max_iter 300 it verifies at its 187th LP)")
    large_stall_very_large: int = _s(
        8, "large", "LPs",
        "large_stall from very_large_min_free free blocks on (2D), where the first start to verify ends "
        "the route: with 16 the 10,050-block benchmark wall verified the same alpha more slowly "
        "(docs/performance.md, 'A longer patience')")
    large_max_iter: int = _s(
        300, "large", "LPs",
        "LPs per start at most (wall family: a 626-block 2D wall's 0.25 mu start verifies at its 187th LP)")
    large_proximal_round: bool = _s(
        True, "large", "-",
        "2D, below prox_min_free free blocks: where no start verifies, the starts run again with each LP "
        "the proximal QP (large_prox), while the budget lasts (wall family: a 3,098-block wall verifies "
        "there and in no start of the first round)")
    large_patience_round_3d: float = _s(
        2.0, "large", "-",
        "3D: where no start verifies, the starts run again with large_stall and large_max_iter this many "
        "times the settings' (1: no second round), while the budget lasts (wall family: a 1,295-block 3D "
        "wall verifies with 32 and 600, in no start with 16 and 300, nor with the proximal QP)")
    large_prox: float = _s(
        0.03, "large", "-",
        "proximal weight of each LP from prox_min_free free blocks on, in 2D, and in the round of "
        "large_proximal_round (limit.solve.iterative_lp's "
        "prox): the normal forces are pulled toward N* so that the statics stop jumping across a "
        "degenerate optimal face")
    large_snap_comp: float = _s(
        1e-3, "large", "alpha units",
        "complementarity residual below which the piece LP snaps the iterate to an exactly "
        "complementary point")
    large_snap_plateau: float = _s(
        1e-2, "large", "alpha units",
        "... and, from the best iterate, when the residual has had no new low for large_plateau LPs "
        "while that low is below this (and below every earlier snap's)")
    large_plateau: int = _s(
        4, "large", "LPs",
        "LPs without a new low of the residual that make a plateau")
    large_snap_comp_very_large: float = _s(
        1e-4, "large", "alpha units",
        "large_snap_comp from very_large_min_free free blocks on (2D): a failed snap costs there more "
        "than several LPs")
    large_snap_plateau_very_large: float = _s(
        1e-3, "large", "alpha units",
        "large_snap_plateau from very_large_min_free free blocks on (2D)")
    large_lp_tol_far: float = _s(
        1e-4, "large", "-",
        "the interior point method's tolerance while the residual is above large_far_comp (far from a "
        "collapse state an exact LP is wasted)")
    large_far_comp: float = _s(
        1e-2, "large", "alpha units",
        "the residual above which LPs are solved to large_lp_tol_far")
    large_lp_tol_near_2d: float = _s(
        1e-7, "large", "-",
        "the tolerance below large_far_comp in 2D (3D: the interior point method's own 1e-9); the snap's "
        "piece LPs and the check are exact regardless")
    large_least_slack_support: float = _s(
        1e-6, "large", "fraction of the largest multiplier",
        "the snap's 'least-slack' rule: the faces that flow are those whose multiplier in the mechanism "
        "closest to complementary exceeds this fraction of the largest")
    large_start_factors: tuple = _s(
        (1.0, 0.5, 0.25), "large", "x mu",
        "friction factors of the starts' associative LPs (1: the associative LP itself)")
    large_start_factors_very_large: tuple = _s(
        (0.5, 0.4), "large", "x mu",
        "the starts from very_large_min_free free blocks on (2D), without the associative LP's own start, "
        "which stalls there")
    large_start_factors_one_round_3d: tuple = _s(
        (0.5, 0.25, 1.0), "large", "x mu",
        "the starts from one_round_min_free free blocks on in 3D, in order (only as many as there are "
        "workers run), the associative LP's own start last: there it is the slowest and not the lowest")
    large_grace: float = _s(
        0.0, "large", "x the first verified start's time",
        "from very_large_min_free free blocks on (2D), once a start has verified at t s the others stop "
        "at t (1 + large_grace): every start that verifies there gives the same alpha", zero_ok=True)

    # -- budget: wall-clock limits -----------------------------------------------------------
    nlp_time_budget: float = _s(
        120.0, "budget", "s",
        "step 2's budget: no restart begins after it once a verified point is in hand "
        "(--nlp-time-budget overrides it)")
    hard_factor: float = _s(
        5.0, "budget", "budgets",
        "without a verified point step 2 goes on up to this many budgets, then stops for good; "
        "its nearby starts (turned load, reduced friction, mirrored reversed load) share that time "
        "(limit.analysis)")
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
    if kind is tuple:
        if not isinstance(v, (tuple, list)) or not v or \
                not all(isinstance(x, (int, float)) and not isinstance(x, bool) and x > 0 for x in v):
            raise ValueError(f"setting {f.name!r}: expected a non-empty tuple of numbers > 0, got {v!r}")
        return tuple(float(x) for x in v)
    ok = (isinstance(v, bool) if kind is bool else
          isinstance(v, int) and not isinstance(v, bool) if kind is int else
          isinstance(v, (int, float)) and not isinstance(v, bool))
    if not ok:
        raise ValueError(f"setting {f.name!r}: expected {kind.__name__}, got {v!r} ({type(v).__name__})")
    if kind is float:
        v = float(v)
        if not (v >= 0 if f.metadata.get("zero_ok") else v > 0):
            raise ValueError(f"setting {f.name!r}: must be {'>=' if f.metadata.get('zero_ok') else '>'} 0, "
                             f"got {v!r}")
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
    (bool: true/false, yes/no, 1/0; tuple: numbers separated by commas); ValueError names the key."""
    key, sep, text = item.partition("=")
    key, text = key.strip(), text.strip()
    if not sep or not key:
        raise ValueError(f"--set {item!r}: expected NAME=VALUE")
    fields = {f.name: f for f in dataclasses.fields(Settings)}
    if key not in fields:
        raise ValueError(f"--set {item!r}: unknown setting {key!r}; valid: {', '.join(fields)}")
    kind = fields[key].type
    try:
        if kind is tuple:
            value = tuple(float(x) for x in text.split(","))
        elif kind is bool:
            low = text.lower()
            if low not in ("true", "false", "yes", "no", "1", "0"):
                raise ValueError
            value = low in ("true", "yes", "1")
        else:
            value = kind(text)
    except ValueError:
        what = "numbers separated by commas" if kind is tuple else kind.__name__
        raise ValueError(f"--set {item!r}: setting {key!r} takes {what}, got {text!r}") from None
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
