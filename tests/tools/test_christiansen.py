"""tools/common/christiansen.py against Christiansen's Whipple shield equations as published,
written here again on their own (the module's code is not read):

    E. L. Christiansen, "Design and performance equations for advanced meteoroid and debris
    shields", Int. J. Impact Eng. 14 (1993) 145–156; NASA TP-2003-210788 ("Meteoroid/Debris
    Shielding", Christiansen 2003), the Whipple shield's ballistic limit equations.

In the published units — lengths cm, densities g/cm³, speeds km/s, the rear wall's yield
stress σ in ksi — with t_b the bumper's and t_w the wall's thickness, S the standoff (bumper
to wall), ρ_p and ρ_b the projectile's and the bumper's density, θ the obliquity:

  V cos θ ≤ 3 km/s (ballistic):
      d_c = [(t_w (σ/40)^0.5 + t_b) / (0.6 (cos θ)^(5/3) ρ_p^0.5 V^(2/3))]^(18/19)
  V cos θ ≥ 7 km/s (hypervelocity):
      d_c = 3.918 t_w^(2/3) ρ_p^(-1/3) ρ_b^(-1/9) (V cos θ)^(-2/3) S^(1/3) (σ/70)^(1/3)
  3 < V cos θ < 7 km/s (shatter, linear in V cos θ between the two):
      d_c = [(t_w (σ/40)^0.5 + t_b) / (1.248 ρ_p^0.5 cos θ)]^(18/19) (1.75 - V cos θ / 4)
          + [1.071 t_w^(2/3) ρ_p^(-1/3) ρ_b^(-1/9) S^(1/3) (σ/70)^(1/3)] (V cos θ / 4 - 0.75)
"""
import math

import pytest

from tools.common import christiansen

PSI = 6894.757293168  # Pa per psi (1 lbf/in²); the module rounds 1 ksi to 6.894757 MPa (4e-8)


def published(V_kms, t_b_cm, t_w_cm, S_cm, rho_p=2.7, rho_b=2.7, sigma_ksi=40.0, theta=0.0):
    """The published equations, in their own units: d_c in cm."""
    c = math.cos(math.radians(theta))
    Vn = V_kms * c
    if Vn <= 3.0:
        return ((t_w_cm * (sigma_ksi / 40.0) ** 0.5 + t_b_cm)
                / (0.6 * c ** (5.0 / 3.0) * rho_p ** 0.5 * V_kms ** (2.0 / 3.0))) ** (18.0 / 19.0)
    if Vn >= 7.0:
        return (3.918 * t_w_cm ** (2.0 / 3.0) * rho_p ** (-1.0 / 3.0) * rho_b ** (-1.0 / 9.0)
                * Vn ** (-2.0 / 3.0) * S_cm ** (1.0 / 3.0) * (sigma_ksi / 70.0) ** (1.0 / 3.0))
    low = ((t_w_cm * (sigma_ksi / 40.0) ** 0.5 + t_b_cm) / (1.248 * rho_p ** 0.5 * c)) ** (18.0 / 19.0)
    high = (1.071 * t_w_cm ** (2.0 / 3.0) * rho_p ** (-1.0 / 3.0) * rho_b ** (-1.0 / 9.0)
            * S_cm ** (1.0 / 3.0) * (sigma_ksi / 70.0) ** (1.0 / 3.0))
    return low * (1.75 - Vn / 4.0) + high * (Vn / 4.0 - 0.75)


def module(V_kms, t_b_cm, t_w_cm, S_cm, rho_p=2.7, rho_b=2.7, sigma_ksi=40.0, theta=0.0):
    """The module's d_c (it takes and returns SI), in cm."""
    return 100.0 * christiansen.critical_diameter(
        V_kms * 1000.0, t_b_cm / 100.0, t_w_cm / 100.0, S_cm / 100.0, rho_p=rho_p * 1000.0,
        rho_b=rho_b * 1000.0, sigma_pa=sigma_ksi * 1000.0 * PSI, theta_deg=theta)


# Shields (t_b, t_w, S in cm; σ in ksi): whipple.yaml's default (1 mm, 2 mm, 30 mm; 6061-T6's
# 40 ksi), a thicker one, and one with a stronger wall and a denser bumper.
SHIELDS = [dict(t_b_cm=0.1, t_w_cm=0.2, S_cm=3.0),
           dict(t_b_cm=0.127, t_w_cm=0.318, S_cm=10.0, sigma_ksi=70.0),
           dict(t_b_cm=0.08, t_w_cm=0.16, S_cm=5.0, rho_b=2.85, sigma_ksi=55.0)]
SPEEDS = {"ballistic": [0.5, 1.0, 2.0, 2.9], "shatter": [3.2, 4.0, 5.0, 6.0, 6.8],
          "hypervelocity": [7.2, 8.0, 10.0, 15.0]}


@pytest.mark.parametrize("shield", SHIELDS)
@pytest.mark.parametrize("regime", list(SPEEDS))
def test_each_regime_at_normal_incidence(shield, regime):
    for V in SPEEDS[regime]:
        assert christiansen.regime(V * 1000.0) == regime
        assert module(V, **shield) == pytest.approx(published(V, **shield), rel=1e-7), V


@pytest.mark.parametrize("theta", [30.0, 45.0, 60.0])
def test_oblique_impact_uses_the_normal_speed(theta):
    shield = SHIELDS[0]
    c = math.cos(math.radians(theta))
    # V cos θ in each regime: 2.5 (ballistic), 5 (shatter), 8 km/s (hypervelocity).
    for vn, regime in ((2.5, "ballistic"), (5.0, "shatter"), (8.0, "hypervelocity")):
        V = vn / c
        assert christiansen.regime(V * 1000.0, theta) == regime
        assert module(V, theta=theta, **shield) == pytest.approx(
            published(V, theta=theta, **shield), rel=1e-7)


@pytest.mark.parametrize("shield", SHIELDS)
@pytest.mark.parametrize("theta", [0.0, 45.0])
def test_continuous_at_the_regime_bounds(shield, theta):
    """The shatter line meets the other two at V cos θ = 3 and 7 km/s (to the rounding of the
    published 1.248 = 0.6 · 3^(2/3) and 1.071 = 3.918 · 7^(-2/3): a few 1e-4)."""
    c = math.cos(math.radians(theta))
    for bound in (3.0, 7.0):
        below = module(bound / c * (1 - 1e-9), theta=theta, **shield)
        above = module(bound / c * (1 + 1e-9), theta=theta, **shield)
        assert above == pytest.approx(below, rel=5e-4), (bound, below, above)


def test_curve_shape():
    """The ballistic limit curve's published shape: d_c falls with speed in the ballistic
    regime, rises through shatter (the projectile breaks up), falls again at hypervelocity."""
    d = {V: module(V, **SHIELDS[0]) for V in (1.0, 2.5, 4.0, 6.5, 8.0, 12.0)}
    assert d[1.0] > d[2.5]
    assert d[2.5] < d[4.0] < d[6.5]
    assert d[8.0] > d[12.0]


def test_si_units():
    """whipple.yaml's default shield at 6.5 km/s: d_c in metres, between 1 and 10 mm."""
    dc = christiansen.critical_diameter(6500.0, 1e-3, 2e-3, 30e-3)
    assert 1e-3 < dc < 1e-2
    assert dc == pytest.approx(published(6.5, 0.1, 0.2, 3.0, sigma_ksi=276e6 / (1000 * PSI)) / 100,
                               rel=1e-7)
