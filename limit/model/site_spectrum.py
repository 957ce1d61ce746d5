"""The elastic spectrum's parameters from the site, NTC 2018 section 3.2.3.2.1.

Given the limit state's hazard parameters on rock (ag/g, F0 and Tc*, in s), the subsoil
category A-E and the topographic category T1-T4:

* SS and CC from Table 3.2.IV (SS = clip(a - b F0 ag/g, lo, hi)):

  ==== ================================ ======================
  soil SS                               CC
  ==== ================================ ======================
  A    1.00                             1.00
  B    1.00 <= 1.40 - 0.40 F0 ag/g <= 1.20  1.10 Tc*^-0.20
  C    1.00 <= 1.70 - 0.60 F0 ag/g <= 1.50  1.05 Tc*^-0.33
  D    0.90 <= 2.40 - 1.50 F0 ag/g <= 1.80  1.25 Tc*^-0.50
  E    1.00 <= 2.00 - 1.10 F0 ag/g <= 1.60  1.15 Tc*^-0.40
  ==== ================================ ======================

* ST from Table 3.2.V, its largest value at the top of the slope or the crest (T1 1.0, T2 1.2,
  T3 1.2, T4 1.4), falling linearly to 1 at the base of the relief: ST = 1 + (ST_max - 1) r
  with r the site's height above the relief's base over the relief's height (1 at the top);
* S = SS ST (eq. 3.2.5), TC = CC Tc* (3.2.7), TB = TC / 3 (3.2.8), TD = 4.0 ag/g + 1.6 s (3.2.9).

The tables are transcribed from the Gazzetta Ufficiale text of the D.M. 17 gennaio 2018.
"""
from __future__ import annotations

from limit.errors import SceneError

#: soil -> (a, b, lo, hi) of SS = clip(a - b F0 ag/g, lo, hi), and (c, p) of CC = c Tc*^-p
SOILS = {
    "A": ((1.00, 0.00, 1.00, 1.00), (1.00, 0.00)),
    "B": ((1.40, 0.40, 1.00, 1.20), (1.10, 0.20)),
    "C": ((1.70, 0.60, 1.00, 1.50), (1.05, 0.33)),
    "D": ((2.40, 1.50, 0.90, 1.80), (1.25, 0.50)),
    "E": ((2.00, 1.10, 1.00, 1.60), (1.15, 0.40)),
}
#: topographic category -> ST at the top of the slope or the crest
TOPOGRAPHY = {"T1": 1.0, "T2": 1.2, "T3": 1.2, "T4": 1.4}


def _number(name: str, value, lo: float, hi: float | None = None, *, open_lo: bool = True) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise SceneError(f"{name}: expected a number, got {value!r}") from None
    if not (v > lo if open_lo else v >= lo) or (hi is not None and v > hi):
        bound = f"{'>' if open_lo else '>='} {lo:g}" + ("" if hi is None else f" and <= {hi:g}")
        raise SceneError(f"{name}: must be {bound}, got {value!r}")
    return v


def site_parameters(ag_g: float, F0: float, Tc_star: float, soil: str = "A", topography: str = "T1",
                    topography_ratio: float = 1.0, where: str = "demand") -> dict:
    """{"SS", "CC", "ST", "S", "TB", "TC", "TD"} (periods in s) of the site (module docstring).
    ``where`` prefixes the names in a rejection (a :class:`SceneError` naming the key)."""
    ag_g = _number(f"{where}.ag_g", ag_g, 0.0)
    F0 = _number(f"{where}.F0", F0, 0.0)
    Tc_star = _number(f"{where}.Tc_star", Tc_star, 0.0)
    r = _number(f"{where}.topography_ratio", topography_ratio, 0.0, 1.0, open_lo=False)
    if soil not in SOILS:
        raise SceneError(f"{where}.soil: must be one of {', '.join(SOILS)} (NTC 2018 Table 3.2.II), got {soil!r}")
    if topography not in TOPOGRAPHY:
        raise SceneError(f"{where}.topography: must be one of {', '.join(TOPOGRAPHY)} (NTC 2018 Table 3.2.III), "
                         f"got {topography!r}")
    (a, b, lo, hi), (c, p) = SOILS[soil]
    SS = min(max(a - b * F0 * ag_g, lo), hi)
    CC = c * Tc_star ** -p
    ST = 1.0 + (TOPOGRAPHY[topography] - 1.0) * r
    TC = CC * Tc_star
    return {"SS": SS, "CC": CC, "ST": ST, "S": SS * ST, "TB": TC / 3.0, "TC": TC, "TD": 4.0 * ag_g + 1.6}
