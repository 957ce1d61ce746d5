"""The seismic demand on a local mechanism and the code check (NTC 2018 section 3.2.3.2.1
for the elastic spectrum; the local-mechanism checks of Circolare 617/2009 C8A.4.9
(linear) and C8A.4.10 (nonlinear, at ground level); above ground, the nonlinear check of
the 2019 Circolare, C8.7.1.2.1.8 with the floor spectrum of C7.2.3).

Elastic horizontal acceleration spectrum (g units times g; T in s), with eta = 1
(5 % damping) unless given:
  0 <= T < TB   Se = ag S eta F0 (T/TB + (1 - T/TB) / (eta F0))
  TB <= T < TC  Se = ag S eta F0
  TC <= T < TD  Se = ag S eta F0 TC / T
  TD <= T       Se = ag S eta F0 TC TD / T^2
and the displacement spectrum SDe(T) = Se(T) (T / 2 pi)^2. eta(xi) = sqrt(10 / (5 + xi%))
>= 0.55 (NTC 2018 eq. 3.2.4, xi in percent).

Checks of a mechanism with spectral activation acceleration a0* and ultimate spectral
displacement du* (secant period Ts), at the life-safety limit state (SLV):
* linear, mechanism at ground level:  a0* >= ag S / q;
* linear, mechanism whose base is at height Z of a building of height H with N storeys
  and first period T1:  a0* >= max(ag S / q, Se(T1) psi(Z) gamma / q), psi = Z / H,
  gamma = 3 N / (2 N + 1);
* nonlinear, at ground level:  du* >= SDe(Ts);
* nonlinear, above ground (Circolare 2019 [C8.7.1.10], [C8.7.1.12]): du* >= SDeZ(T_SLV) with
  T_SLV = 1.68 pi sqrt(du* / a*(du*)) (du* = 0.4 d0*, the SLV displacement of C8.7.1.2.1.6)
  and SDeZ(T) = SeZ(T) T^2 / 4 pi^2, kept at least SeZ(T1) (b T1)^2 / 4 pi^2 beyond b T1.
  SeZ is the floor spectrum of the first mode ([C7.2.5]-[C7.2.10]), with the building's
  damping xi1 and the mechanism's xi (8 % at SLV by default, C8.7.1.2.1.8):
    aZ = Se(T1, xi1) gamma psi(Z) sqrt(1 + 0.0004 xi1%^2)      [C7.2.7], [C7.2.10]
    A = 1.1 xi1^-0.5 eta(xi)                                     [C7.2.6], [C7.2.9]
    T < a T1:        SeZ = A aZ / (1 + (A - 1) (1 - T / (a T1))^1.6)
    a T1 <= T < b T1: SeZ = A aZ
    T >= b T1:       SeZ = A aZ / (1 + (A - 1) (T / (b T1) - 1)^1.2)
  and SeZ >= Se(T, xi) for T > T1 [C7.2.5]; a = 0.8, b = 1.1.
  The unit of xi1: the Circolare's text (a transcription, github.com/claudiopagani/
  structural-codes, corpus/assets/circ2019/7.2.json; the official PDF was not available)
  calls xi_k "in percent". In the power 1.1 xi1^-0.5 that gives A = 0.49 at 5 %, a floor
  spectrum below the floor's own peak acceleration aZ (its value at T = 0), which is
  physically wrong; with xi1 as a fraction A = 4.92 at 5 %, the a_p = 5 of the same
  section's simplified floor spectrum [C7.2.11] (Table C7.2.II, T1 < 0.5 s), the order of
  the resonant amplification of a 5 %-damped oscillator on a floor. So xi1 enters the power as a fraction
  (the larger, safe-side demand) and sqrt(1 + 0.0004 xi1^2) in percent (it is the
  pseudo-to-absolute acceleration factor sqrt(1 + 4 xi^2)). The ground-level check keeps
  2009's Ts: the 2019 Circolare evaluates SDe at T_SLV there too (not applied here).
q = 2 is the code's behaviour factor for these mechanisms. Ratios capacity / demand >= 1
pass.

With the damage limit state's hazard (the demand's ``SLD``: its ag_g, F0, Tc*), the linear
damage check of Circolare 617/2009 C8A.4.2.3 goes beside them, on the SLD's elastic spectrum
with no behaviour factor:
* at ground level:  a0* >= ag S                               (C8A.4.7)
* above ground:     a0* >= max(ag S, Se(T1) psi(Z) gamma)      (C8A.4.8, with the ground's as for SLV)
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

G = 9.81

#: the floor spectrum's plateau bounds, as fractions of T1 ([C7.2.6]: "may be taken as")
FLOOR_A, FLOOR_B = 0.8, 1.1
#: T_SLV = SLV_PERIOD pi sqrt(d_SLV / a(d_SLV)) (Circolare 2019 [C8.7.1.10])
SLV_PERIOD = 1.68


def eta_of(xi: float) -> float:
    """Damping correction of the elastic spectrum for a damping ratio ``xi`` (fraction):
    sqrt(10 / (5 + 100 xi)) >= 0.55 (NTC 2018 eq. 3.2.4)."""
    return max(math.sqrt(10.0 / (5.0 + 100.0 * xi)), 0.55)


@dataclass(frozen=True)
class Demand:
    """The site's spectrum and the mechanism's position. ``ag_g``: peak ground acceleration
    on rock (in g); ``S``: soil and topography factor; ``F0``: spectral amplification;
    ``TB``, ``TC``, ``TD`` (s): corner periods; ``q``: behaviour factor (2 for local
    mechanisms); ``eta``: damping correction; ``Z``, ``H`` (m), ``N``, ``T1`` (s): the base
    height of the mechanism, the building's height, storeys and first period (Z = 0: at
    ground level); ``xi1``: the building's first-mode equivalent damping (fraction; 0.05
    elastic, 0.10-0.20 for a masonry building at the ultimate state, Circolare 2019
    C8.7.1.2.1.4); ``xi_mech``: the mechanism's damping at SLV (fraction, 0.08 by default,
    C8.7.1.2.1.8). ``xi1`` and ``xi_mech`` enter only the nonlinear check above ground.
    ``site``: how S, TB, TC and TD were derived from the site (:func:`from_mapping`), None when
    they were given."""

    ag_g: float
    S: float = 1.0
    F0: float = 2.5
    TB: float = 0.15
    TC: float = 0.5
    TD: float = 2.0
    q: float = 2.0
    eta: float = 1.0
    Z: float = 0.0
    H: float | None = None
    N: int | None = None
    T1: float | None = None
    xi1: float = 0.05
    xi_mech: float = 0.08
    site: dict | None = field(default=None, compare=False)
    #: the damage limit state's demand (same site and position, its own hazard), or None
    sld: "Demand | None" = field(default=None, compare=False)

    def __post_init__(self):
        for k in ("ag_g", "S", "F0", "TB", "TC", "TD", "q", "eta", "xi1", "xi_mech"):
            v = getattr(self, k)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"demand.{k}: must be a positive number, got {v!r}")
        if not self.TB < self.TC < self.TD:
            raise ValueError(f"demand: need TB < TC < TD, got {self.TB}, {self.TC}, {self.TD}")
        if self.Z < 0:
            raise ValueError(f"demand.Z: must be >= 0, got {self.Z!r}")
        if self.Z > 0 and not (self.H and self.N and self.T1 and self.H >= self.Z):
            raise ValueError("demand: a mechanism above ground (Z > 0) needs H >= Z, N and T1")
        for k in ("xi1", "xi_mech"):
            if getattr(self, k) >= 1.0:
                raise ValueError(f"demand.{k}: a damping ratio as a fraction (0.05 for 5 %), got {getattr(self, k)!r}")

    def Se(self, T: float, eta: float | None = None) -> float:
        """Elastic spectral acceleration (m/s^2) at period T (s), with damping correction
        ``eta`` (default: the demand's)."""
        eta = self.eta if eta is None else eta
        a = self.ag_g * G * self.S * eta * self.F0
        if T < self.TB:
            return a * (T / self.TB + (1.0 - T / self.TB) / (eta * self.F0))
        if T < self.TC:
            return a
        if T < self.TD:
            return a * self.TC / T
        return a * self.TC * self.TD / T ** 2

    def SDe(self, T: float) -> float:
        """Elastic spectral displacement (m) at period T (s)."""
        return self.Se(T) * (T / (2 * math.pi)) ** 2

    def floor_peak(self) -> float:
        """aZ (m/s^2): the floor's peak acceleration at the mechanism's base from the first
        mode, Se(T1, xi1) gamma psi(Z) sqrt(1 + 0.0004 xi1%^2) ([C7.2.7], [C7.2.10])."""
        gamma, psi = 3.0 * self.N / (2.0 * self.N + 1.0), self.Z / self.H
        return self.Se(self.T1, eta_of(self.xi1)) * gamma * psi * math.sqrt(1.0 + 0.0004 * (100.0 * self.xi1) ** 2)

    def floor_amplification(self) -> float:
        """A = 1.1 xi1^-0.5 eta(xi_mech), xi1 as a fraction ([C7.2.6]; the module docstring says why)."""
        return 1.1 * self.xi1 ** -0.5 * eta_of(self.xi_mech)

    def SeZ(self, T: float) -> float:
        """The floor spectrum (m/s^2) at the mechanism's base for period T (s), first mode
        ([C7.2.5], [C7.2.6]; at least the ground's Se(T, xi_mech) beyond T1)."""
        A, aZ, T1 = self.floor_amplification(), self.floor_peak(), self.T1
        if T < FLOOR_A * T1:
            s = A * aZ / (1.0 + (A - 1.0) * (1.0 - T / (FLOOR_A * T1)) ** 1.6)
        elif T < FLOOR_B * T1:
            s = A * aZ
        else:
            s = A * aZ / (1.0 + (A - 1.0) * (T / (FLOOR_B * T1) - 1.0) ** 1.2)
        return max(s, self.Se(T, eta_of(self.xi_mech))) if T > T1 else s

    def SDeZ(self, T: float) -> float:
        """The floor displacement spectrum (m): SeZ(T) T^2 / 4 pi^2, at least SeZ(T1) (b T1)^2 /
        4 pi^2 beyond b T1 (Circolare 2019 [C8.7.1.12])."""
        d = self.SeZ(T) * (T / (2 * math.pi)) ** 2
        if T > FLOOR_B * self.T1:
            d = max(d, self.SeZ(self.T1) * (FLOOR_B * self.T1 / (2 * math.pi)) ** 2)
        return d


def slv_period(du_star: float, au_star: float) -> float:
    """T_SLV (s) = 1.68 pi sqrt(du* / a*(du*)) (Circolare 2019 [C8.7.1.10]; m, m/s^2)."""
    return SLV_PERIOD * math.pi * math.sqrt(du_star / au_star)


#: the site's keys of a demand (limit.model.site_spectrum): with them S, TB, TC and TD are derived
SITE_KEYS = ("Tc_star", "soil", "topography", "topography_ratio")
#: the spectrum's keys that the site derives, and that an explicit value overrides
DERIVED_KEYS = ("S", "TB", "TC", "TD")


def from_mapping(d: dict, where: str = "demand") -> Demand:
    """A :class:`Demand` from a scene file's ``demand`` object (or the ``limit check`` options).

    With any of :data:`SITE_KEYS`, S, TB, TC and TD come from the site (NTC 2018 section
    3.2.3.2.1, :func:`limit.model.site_spectrum.site_parameters`; ``Tc_star`` and ``F0`` are then
    required, ``soil`` defaults to A, ``topography`` to T1, ``topography_ratio`` to 1); an explicit
    S, TB, TC or TD overrides the derived value, and ``Demand.site`` records both. Keys that are
    not a Demand's (the scene loader has warned about them already, or rejected them under
    ``--strict``) are ignored. Raises ValueError naming the key (``where``.key)."""
    from limit.model.site_spectrum import site_parameters

    names = {f.name for f in fields(Demand)} - {"site", "sld"}
    kw = {k: v for k, v in d.items() if k in names}
    sld = None
    if d.get("SLD") is not None:
        own = d["SLD"]
        if not isinstance(own, dict):
            raise ValueError(f"{where}.SLD: an object with the damage limit state's ag_g (and F0, Tc_star)")
        # the mechanism's position is the demand's; so is the site (soil, topography), whose spectrum
        # the SLD's own ag_g, F0 and Tc_star then give, or else the demand's explicit S and corners
        keys = ("Z", "H", "N", "T1", "eta", "xi1")
        keys += ("soil", "topography", "topography_ratio") if any(k in d for k in SITE_KEYS) else DERIVED_KEYS + ("F0",)
        shared = {k: d[k] for k in keys if k in d}
        sld = from_mapping({**shared, **{k: v for k, v in own.items() if k in names | {"Tc_star"}}}, f"{where}.SLD")
    if "ag_g" not in kw:
        raise ValueError(f"{where}.ag_g: required (the peak ground acceleration on rock, in g)")
    if any(k in d for k in SITE_KEYS):
        for k in ("Tc_star", "F0"):
            if k not in d:
                raise ValueError(f"{where}.{k}: required with the site's soil and topography (NTC 2018 3.2.3.2.1: "
                                 "ag_g, F0 and Tc_star of the limit state)")
        par = site_parameters(d["ag_g"], d["F0"], d["Tc_star"], d.get("soil", "A"), d.get("topography", "T1"),
                              d.get("topography_ratio", 1.0), where)  # its SceneError is a ValueError
        given = {k: kw[k] for k in DERIVED_KEYS if k in kw}
        kw = {**{k: par[k] for k in DERIVED_KEYS}, **kw}
        kw["site"] = {"code": "NTC 2018 3.2.3.2.1", "Tc_star": float(d["Tc_star"]), "soil": d.get("soil", "A"),
                      "topography": d.get("topography", "T1"),
                      "topography_ratio": float(d.get("topography_ratio", 1.0)), "SS": par["SS"], "CC": par["CC"],
                      "ST": par["ST"], "derived": {k: par[k] for k in DERIVED_KEYS}, "overridden": given}
    return Demand(**kw, sld=sld)


def as_dict(demand: Demand) -> dict:
    """The demand's fields as a plain dict (the result file's ``verdict.demand``; its SLD's under
    ``SLD``)."""
    out = {f.name: getattr(demand, f.name) for f in fields(Demand) if f.name != "sld"}
    if demand.sld is not None:
        out["SLD"] = as_dict(demand.sld)
    return out


def linear_demand(d: Demand, q: float) -> float:
    """The linear check's demand (m/s^2): ag S / q at ground level; above ground at least
    Se(T1) psi(Z) gamma / q (module docstring)."""
    need = d.ag_g * G * d.S / q
    if d.Z > 0:
        psi, gamma = d.Z / d.H, 3.0 * d.N / (2.0 * d.N + 1.0)
        need = max(need, d.Se(d.T1) * psi * gamma / q)
    return need


def check(demand: Demand, a0_star: float, du_star: float | None = None, Ts: float | None = None,
          au_star: float | None = None) -> dict:
    """The linear (and, with du* and Ts, the nonlinear) check: {"linear": {"demand" m/s^2,
    "capacity", "ratio", "pass"}, "nonlinear": {"demand" m, "capacity" m, "ratio", "pass",
    "period" s, "rule"} or None (without a capacity curve, or above ground without a*(du*)
    ``au_star`` > 0, m/s^2), "nonlinear_reason" (why None, else ""), "damage": the linear SLD
    check {"demand" m/s^2, "capacity", "ratio", "pass"} with the demand's ``sld``, else None}."""
    d = demand
    need = linear_demand(d, d.q)
    lin = {"demand": need, "capacity": a0_star, "ratio": a0_star / need, "pass": a0_star >= need}
    damage = None
    if d.sld is not None:
        nd = linear_demand(d.sld, 1.0)
        damage = {"demand": nd, "capacity": a0_star, "ratio": a0_star / nd, "pass": a0_star >= nd}
    nonlin, why = None, ""
    if du_star is None or Ts is None:
        why = "no capacity curve"
    elif d.Z > 0 and not (au_star and au_star > 0):
        why = "the mechanism is above ground and its capacity curve has no acceleration at du* (for T_SLV)"
    elif d.Z > 0:
        T = slv_period(du_star, au_star)
        dd = d.SDeZ(T)
        nonlin = {"demand": dd, "capacity": du_star, "ratio": du_star / dd, "pass": du_star >= dd, "period": T,
                  "rule": "SDeZ(T_SLV)", "Ts": Ts}
    else:
        dd = d.SDe(Ts)
        nonlin = {"demand": dd, "capacity": du_star, "ratio": du_star / dd, "pass": du_star >= dd, "period": Ts,
                  "rule": "SDe(Ts)", "Ts": Ts}
    return {"linear": lin, "nonlinear": nonlin, "nonlinear_reason": why, "damage": damage}
