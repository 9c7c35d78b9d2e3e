#!/usr/bin/python3
"""Writes the family of wavy bars (sim/scenes/curved/*.yaml): the bent bar's
start and program (bent_bar_fused), the bar's top edge a sine in height along
the slide, z = z0 + A sin(2 pi s / L) (s along the bar), so the edge's
smallest radius of curvature, at the crests and troughs, is
R = L^2 / (4 pi^2 A). The rigid pad reaches 47.6 mm along the edge (14 taxels
of 3.4 mm): a trough tighter than the pad touches its ends (the housing)
instead of its middle. Usage: make_curved_bars.py [--out sim/scenes/curved]
"""
import argparse
import math
import os

# At most 65 vertices (the simulator's bar): 6 mm apart, 6.7 per wavelength at 40 mm.
# (amplitude m, wavelength m): R from 243 mm down to 13.5 mm.
FAMILY = [(0.0015, 0.120), (0.002, 0.120), (0.003, 0.120), (0.0015, 0.090), (0.002, 0.090), (0.0015, 0.070),
          (0.003, 0.090), (0.003, 0.070), (0.003, 0.060), (0.003, 0.050), (0.003, 0.040)]
X0, X1, Z0 = 0.78, 0.42, 0.368  # the bent bar's straight start: x from X0 to X1 along -x_g, top at Z0
FLAT = 0.11  # m of straight bar from X0 before the waves: under the whole pad at the start (first contact, alignment, the start of the slide)


def radius(a, l):
    return l * l / (4.0 * math.pi * math.pi * a)


def vertices(a, l, step=0.006):
    out = []
    n = int(round((X0 - X1) / step))
    for i in range(n + 1):
        s = i * step
        z = Z0 + (a * math.sin(2.0 * math.pi * (s - FLAT) / l) if s > FLAT else 0.0)
        out.append([round(X0 - s, 6), 0.0, round(z, 6)])
    return out


def scene(a, l):
    name = f"wavy_a{a * 1e3:g}mm_l{l * 1e3:g}mm"
    v = ", ".join(f"[{x[0]}, {x[1]}, {x[2]}]" for x in vertices(a, l))
    return name, f"""# Wavy bar (scripts/tools/make_curved_bars.py): the bent bar's start, its top edge
# a sine in height after {FLAT * 1e3:g} mm of straight bar: amplitude {a * 1e3:g} mm, wavelength
# {l * 1e3:g} mm, smallest radius of curvature along the edge {radius(a, l) * 1e3:.1f} mm (the pad
# reaches 47.6 mm). Shipped program bent_bar_to_end_cap.yaml.
name: {name}
description: "Wavy bar, A {a * 1e3:g} mm, L {l * 1e3:g} mm, R {radius(a, l) * 1e3:.1f} mm"
program: ../../../components/servo/programs/bent_bar_to_end_cap.yaml
features_file: ../../../components/features/params/wts0614.yaml
controller: proposed
duration: 22
seed: 1
fidelity: quasi_static
rates: {{sim: 1000, servo: 100, wts: 140, features: 200}}
sensor: {{subsamples: 4, physics_subsamples: 2}}
initial_flange: {{xyz: [0.72, 0.0, 0.413], rpy_deg: [180, 0, 180]}}
objects:
  - name: wavy_bar
    type: bent_bar
    radius: 0.005
    vertices: [{v}]
effects:
  wrench_error: {{bias_n: [1.0, -1.0, 2.0], noise_n: 0.5}}
metrics:
  transient_s: 2.0
  force_phases: [explore]
  force_band_n: 0.5
  criteria:
    force_true_max_n: {{max: 7.0}}
    force_true_rms_error_n: {{max: 0.4}}
    force_true_in_band_fraction: {{min: 0.95}}
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "..", "sim", "scenes", "curved"))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    for amp, l in FAMILY:
        name, text = scene(amp, l)
        with open(os.path.join(a.out, name + ".yaml"), "w") as fh:
            fh.write(text)
        print(f"{name}: R = {radius(amp, l) * 1e3:.1f} mm")


if __name__ == "__main__":
    main()
