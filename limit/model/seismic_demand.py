"""The seismic demand on a local mechanism and the code check (NTC 2018 section 3.2.3.2.1
for the elastic spectrum; the local-mechanism checks of Circolare 617/2009 C8A.4.9
(linear) and C8A.4.10 (nonlinear), which the 2019 Circolare's C8.7.1 carries over for
mechanisms at ground level).

Elastic horizontal acceleration spectrum (g units times g; T in s), with eta = 1
(5 % damping) unless given:
  0 <= T < TB   Se = ag S eta F0 (T/TB + (1 - T/TB) / (eta F0))
  TB <= T < TC  Se = ag S eta F0
  TC <= T < TD  Se = ag S eta F0 TC / T
  TD <= T       Se = ag S eta F0 TC TD / T^2
and the displacement spectrum SDe(T) = Se(T) (T / 2 pi)^2.

Checks of a mechanism with spectral activation acceleration a0* and ultimate spectral
displacement du* (secant period Ts):
* linear, mechanism at ground level:  a0* >= ag S / q;
* linear, mechanism whose base is at height Z of a building of height H with N storeys
  and first period T1:  a0* >= max(ag S / q, Se(T1) psi(Z) gamma / q), psi = Z / H,
  gamma = 3 N / (2 N + 1);
* nonlinear, at ground level:  du* >= SDe(Ts).
q = 2 is the code's behaviour factor for these mechanisms. Ratios capacity / demand >= 1
pass.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

G = 9.81

#: why the nonlinear check of a mechanism above ground is not made. The 2019 Circolare takes its
#: displacement demand ([C8.7.1.12], section C8.7.1.2.1.8) from the floor spectrum of C7.2.3
#: ([C7.2.5]-[C7.2.9]), with its own secant periods (T_SLV = 1.68 pi sqrt(d/a), [C8.7.1.10]) rather
#: than the ground-level Ts used here. The only copy found offline (a transcription,
#: github.com/claudiopagani/structural-codes, corpus/assets/circ2019/7.2.json, not the official
#: PDF) gives the damping xi_k of the building's mode "in percentuale", which makes the resonant
#: amplification 1.1 xi_k^-0.5 eta of [C7.2.6] smaller than 1 (0.43 at 5 %): a floor spectrum
#: below the floor's own acceleration. Not implemented until read in the official text.
ABOVE_GROUND_NONLINEAR = ("the mechanism is above ground (Z > 0): its displacement demand (the floor spectrum of the "
                          "2019 Circolare, C7.2.3 and C8.7.1.2.1.8) is not implemented: the only copy found gives "
                          "the building's damping in percent, which makes the floor spectrum's resonant "
                          "amplification smaller than 1; it needs the official text")


@dataclass(frozen=True)
class Demand:
    """The site's spectrum and the mechanism's position. ``ag_g``: peak ground acceleration
    on rock (in g); ``S``: soil and topography factor; ``F0``: spectral amplification;
    ``TB``, ``TC``, ``TD`` (s): corner periods; ``q``: behaviour factor (2 for local
    mechanisms); ``eta``: damping correction; ``Z``, ``H`` (m), ``N``, ``T1`` (s): the base
    height of the mechanism, the building's height, storeys and first period (Z = 0: at
    ground level)."""

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

    def __post_init__(self):
        for k in ("ag_g", "S", "F0", "TB", "TC", "TD", "q", "eta"):
            v = getattr(self, k)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"demand.{k}: must be a positive number, got {v!r}")
        if not self.TB < self.TC < self.TD:
            raise ValueError(f"demand: need TB < TC < TD, got {self.TB}, {self.TC}, {self.TD}")
        if self.Z < 0:
            raise ValueError(f"demand.Z: must be >= 0, got {self.Z!r}")
        if self.Z > 0 and not (self.H and self.N and self.T1 and self.H >= self.Z):
            raise ValueError("demand: a mechanism above ground (Z > 0) needs H >= Z, N and T1")

    def Se(self, T: float) -> float:
        """Elastic spectral acceleration (m/s^2) at period T (s)."""
        a = self.ag_g * G * self.S * self.eta * self.F0
        if T < self.TB:
            return a * (T / self.TB + (1.0 - T / self.TB) / (self.eta * self.F0))
        if T < self.TC:
            return a
        if T < self.TD:
            return a * self.TC / T
        return a * self.TC * self.TD / T ** 2

    def SDe(self, T: float) -> float:
        """Elastic spectral displacement (m) at period T (s)."""
        return self.Se(T) * (T / (2 * math.pi)) ** 2


def check(demand: Demand, a0_star: float, du_star: float | None = None, Ts: float | None = None) -> dict:
    """The linear (and, with du* and Ts, the nonlinear) check: {"linear": {"demand" m/s^2,
    "capacity", "ratio", "pass"}, "nonlinear": {...} or None (above ground, or without a
    capacity curve), "nonlinear_reason" (why None, else "")}."""
    d = demand
    need = d.ag_g * G * d.S / d.q
    if d.Z > 0:
        psi, gamma = d.Z / d.H, 3.0 * d.N / (2.0 * d.N + 1.0)
        need = max(need, d.Se(d.T1) * psi * gamma / d.q)
    lin = {"demand": need, "capacity": a0_star, "ratio": a0_star / need, "pass": a0_star >= need}
    nonlin, why = None, ""
    if du_star is None or Ts is None:
        why = "no capacity curve"
    elif d.Z > 0:
        why = ABOVE_GROUND_NONLINEAR
    else:
        dd = d.SDe(Ts)
        nonlin = {"demand": dd, "capacity": du_star, "ratio": du_star / dd, "pass": du_star >= dd, "Ts": Ts}
    return {"linear": lin, "nonlinear": nonlin, "nonlinear_reason": why}
