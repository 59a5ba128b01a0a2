#!/usr/bin/python3
"""The Christiansen ballistic limit equations of a Whipple shield (aluminium bumper, standoff,
aluminium rear wall) for a spherical aluminium projectile: the critical projectile diameter,
the largest the shield stops, at impact speed V and obliquity θ.

E. L. Christiansen, "Design and performance equations for advanced meteoroid and debris
shields", Int. J. Impact Eng. 14 (1993) 145–156; as used by NASA (Christiansen, "Meteoroid/
Debris Shielding", NASA TP-2003-210788, the Whipple shield equations). In the equations' units
(cm, g/cm³, km/s, ksi), with t_b the bumper and t_w the wall thickness, S the standoff, σ the
wall's yield stress, ρ_p and ρ_b the projectile's and bumper's densities, Vn = V cos θ:

  ballistic, Vn ≤ 3 km/s:
      d_c = [(t_w (σ/40)^0.5 + t_b) / (0.6 (cos θ)^(5/3) ρ_p^0.5 V^(2/3))]^(18/19)
  hypervelocity, Vn ≥ 7 km/s:
      d_c = 3.918 t_w^(2/3) ρ_p^(−1/3) ρ_b^(−1/9) (V cos θ)^(−2/3) S^(1/3) (σ/70)^(1/3)
  shatter, 3 < Vn < 7 km/s: the straight line in Vn between the two at 3 and 7 km/s,
      d_c = [(t_w (σ/40)^0.5 + t_b) / (1.248 ρ_p^0.5 cos θ)]^(18/19) (1.75 − Vn/4)
            + 1.071 t_w^(2/3) ρ_p^(−1/3) ρ_b^(−1/9) S^(1/3) (σ/70)^(1/3) (Vn/4 − 0.75)

(1.248 = 0.6 · 3^(2/3), 1.071 = 3.918 · 7^(−2/3): the line meets the two regimes' equations at
its ends.) The function takes and returns SI units.

    tools/common/christiansen.py      prints the default whipple.yaml shield's curve, 1–10 km/s

Import it for the function: `from tools.common.christiansen import critical_diameter`
(tests/tools/test_christiansen.py checks it against the published equations)."""
import math

KSI = 6.894757e6  # Pa


def critical_diameter(v, tb, tw, standoff, rho_p=2700.0, rho_b=2700.0, sigma_pa=276e6,
                      theta_deg=0.0):
    """The critical diameter (m) at speed v (m/s); lengths in m, densities kg/m³, σ in Pa."""
    c = math.cos(math.radians(theta_deg))
    V = v / 1000.0
    vn = V * c
    t_b, t_w, s = tb * 100.0, tw * 100.0, standoff * 100.0  # cm
    rp, rb = rho_p / 1000.0, rho_b / 1000.0                  # g/cm³
    sigma = sigma_pa / KSI                                   # ksi
    wall = t_w * (sigma / 40.0) ** 0.5 + t_b
    hyper_k = t_w ** (2 / 3) * rp ** (-1 / 3) * rb ** (-1 / 9) * s ** (1 / 3) * (sigma / 70.0) ** (1 / 3)
    if vn <= 3.0:
        d = (wall / (0.6 * c ** (5 / 3) * rp ** 0.5 * V ** (2 / 3))) ** (18 / 19)
    elif vn >= 7.0:
        d = 3.918 * hyper_k * vn ** (-2 / 3)
    else:
        d = ((wall / (1.248 * rp ** 0.5 * c)) ** (18 / 19) * (1.75 - vn / 4.0)
             + 1.071 * hyper_k * (vn / 4.0 - 0.75))
    return d / 100.0


def regime(v, theta_deg=0.0):
    """'ballistic', 'shatter' or 'hypervelocity': the equation critical_diameter uses."""
    vn = v / 1000.0 * math.cos(math.radians(theta_deg))
    return "ballistic" if vn <= 3.0 else "hypervelocity" if vn >= 7.0 else "shatter"


if __name__ == "__main__":
    # The default shield of data/cases/whipple.yaml: 1 mm bumper, 30 mm standoff, 2 mm wall.
    for v in range(1000, 10001, 500):
        print(f"{v:6d} m/s  d_c = {critical_diameter(v, 1e-3, 2e-3, 30e-3) * 1e3:.3f} mm  "
              f"({regime(v)})")
