#!/usr/bin/python3
"""Writes the family of bars of params/scenes/curved/*.yaml, each starting as the
bent bar does (the start pose and program of bent_bar_fused, 110 mm of
straight bar under the pad), then:
  wavy_*      the top edge a sine in height along the slide,
              z = z0 + A sin(2 pi s / L) (s along the bar), so the edge's
              smallest radius of curvature, at the crests and troughs, is
              R = L^2 / (4 pi^2 A). The rigid pad reaches 47.6 mm along the
              edge (14 taxels of 3.4 mm): a trough tighter than the pad
              touches its ends (the housing) instead of its middle;
  dip_*       one raised-cosine trough of depth D over W (R = W^2 / (2 pi^2 D));
  step_*      a raised-cosine step of height H (up, or down) over W
              (R = 2 W^2 / (pi^2 H));
  bend_*      the bent bar's parabolic bend (30 mm sideways, 25 mm in height
              over 247 mm), mirrored: to the right, or down (away from the pad);
  sharp_*     a straight bar with a top edge rounded at 2 mm instead of 5 mm.
Usage: make_curved_bars.py [--out params/scenes/curved]
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


def polyline(offset, step=0.006):
    """Vertices every `step` along the bar: offset(u) = (y, z) of the centreline
    at u = s - FLAT metres into the shape (0 before it)."""
    out = []
    n = int(round((X0 - X1) / step))
    for i in range(n + 1):
        s = i * step
        y, z = offset(s - FLAT) if s > FLAT else (0.0, 0.0)
        out.append([round(X0 - s, 6), round(y, 6), round(Z0 + z, 6)])
    return out


def vertices(a, l, step=0.006):
    return polyline(lambda u: (0.0, a * math.sin(2.0 * math.pi * u / l)), step)


def dip(depth, width):
    """A raised-cosine trough: 0 outside [0, width]."""
    return lambda u: (0.0, -0.5 * depth * (1.0 - math.cos(2.0 * math.pi * u / width)) if u < width else 0.0)


def step_shape(height, width):
    """A raised-cosine step of `height` (m, signed) over `width`."""
    return lambda u: (0.0, 0.5 * height * (1.0 - math.cos(math.pi * min(u, width) / width)))


BEND_LEN, BEND_Y, BEND_Z = 0.2475, 0.03, 0.025  # the bent bar's bend (params/scenes/bent_bar.yaml): parabolic


def bend(sy, sz):
    """The bent bar's bend, sideways sy * 30 mm and in height sz * 25 mm at its end."""
    return lambda u: (sy * BEND_Y * (u / BEND_LEN) ** 2, sz * BEND_Z * (u / BEND_LEN) ** 2)


# name, description, offset, the top edge's rounding radius (m)
SHAPES = [("dip_d2mm_w80mm", "one trough 2 mm deep over 80 mm, R 162 mm", dip(0.002, 0.08), 0.005),
          ("dip_d3mm_w60mm", "one trough 3 mm deep over 60 mm, R 61 mm", dip(0.003, 0.06), 0.005),
          ("step_up_2mm_w40mm", "a step up of 2 mm over 40 mm, R 162 mm", step_shape(0.002, 0.04), 0.005),
          ("step_down_2mm_w40mm", "a step down of 2 mm over 40 mm, R 162 mm", step_shape(-0.002, 0.04), 0.005),
          ("bend_right", "the bent bar's bend mirrored: to the right and up", bend(-1.0, 1.0), 0.005),
          ("bend_down", "the bent bar's bend dipping away: to the left and down", bend(1.0, -1.0), 0.005),
          ("bend_right_down", "the bent bar's bend to the right and down", bend(-1.0, -1.0), 0.005),
          ("sharp_r2mm", "a straight bar, its top edge rounded at 2 mm", lambda u: (0.0, 0.0), 0.002)]


# The force targets of a bar that is followed to its end.
FOLLOWED = """    force_true_max_n: {max: 7.0}
    force_true_rms_error_n: {max: 0.4}
    force_true_in_band_fraction: {min: 0.95}"""


def scene_text(name, header, description, verts, rounding=0.005, up="../..",
               duration=22, criteria=FOLLOWED):
    """A scene of the family: the bent bar's start, pose and criteria (its program: experiments.yaml)."""
    v = ", ".join(f"[{x[0]}, {x[1]}, {x[2]}]" for x in verts)
    return f"""{header}
name: {name}
description: "{description}"
features_file: {up}/sensors/wts0614.yaml
duration: {duration}
seed: 1
fidelity: quasi_static
rates: {{sim: 1000, servo: 100, wts: 140, features: 200}}
sensor: {{subsamples: 4, physics_subsamples: 2}}
initial_flange: {{xyz: [0.72, 0.0, 0.413], rpy_deg: [180, 0, 180]}}
objects:
  - name: wavy_bar
    type: bent_bar
    radius: {rounding:g}
    vertices: [{v}]
effects:
  wrench_error: {{bias_n: [1.0, -1.0, 2.0], noise_n: 0.5}}
metrics:
  transient_s: 2.0
  force_phases: [explore]
  force_band_n: 0.5
  criteria:                       # the force: the scored window (explore after its 2 s transient)
{criteria}
"""


def scene(a, l):
    name = f"wavy_a{a * 1e3:g}mm_l{l * 1e3:g}mm"
    header = f"""# Wavy bar (scripts/tools/make_curved_bars.py): the bent bar's start, its top edge
# a sine in height after {FLAT * 1e3:g} mm of straight bar: amplitude {a * 1e3:g} mm, wavelength
# {l * 1e3:g} mm, smallest radius of curvature along the edge {radius(a, l) * 1e3:.1f} mm (the pad
# reaches 47.6 mm). Its program: experiments.yaml, scenes:."""
    return name, scene_text(name, header, f"Wavy bar, A {a * 1e3:g} mm, L {l * 1e3:g} mm, R {radius(a, l) * 1e3:.1f} mm",
                            vertices(a, l))


def shape_scene(name, what, offset, rounding):
    header = f"""# Bar of the family (scripts/tools/make_curved_bars.py): the bent bar's start, then
# after {FLAT * 1e3:g} mm of straight bar {what}. Its program: experiments.yaml, scenes:."""
    return scene_text(name, header, f"Bar: {what}", polyline(offset), rounding)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "..", "params", "scenes", "curved"))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    for amp, l in FAMILY:
        name, text = scene(amp, l)
        with open(os.path.join(a.out, name + ".yaml"), "w") as fh:
            fh.write(text)
        print(f"{name}: R = {radius(amp, l) * 1e3:.1f} mm")
    for name, what, offset, rounding in SHAPES:
        with open(os.path.join(a.out, name + ".yaml"), "w") as fh:
            fh.write(shape_scene(name, what, offset, rounding))
        print(f"{name}: {what}")
    # The registry's experiment of the careful speed law (experiments.yaml
    # wave_speed_law): the A 2 mm, L 90 mm wave with bent_bar_speed_law_careful.yaml,
    # long enough for its slide, beside the other experiments' scenes.
    amp, l = 0.002, 0.090
    header = f"""# The careful speed law on a wave (scripts/tools/make_curved_bars.py; experiments.yaml
# wave_speed_law): params/scenes/curved/wavy_a{amp * 1e3:g}mm_l{l * 1e3:g}mm.yaml (R {radius(amp, l) * 1e3:.1f} mm) with
# bent_bar_speed_law_careful.yaml, 40 s. docs/design.md, "The speed law"."""
    with open(os.path.join(a.out, "..", "wave_speed_law.yaml"), "w") as fh:
        fh.write(scene_text("wave_speed_law", header, f"A wave in height (A {amp * 1e3:g} mm, L {l * 1e3:g} mm, R "
                            f"{radius(amp, l) * 1e3:.1f} mm), the careful speed law", vertices(amp, l),
                            up="..", duration=40))
    print("wave_speed_law: the careful speed law on the A 2 mm, L 90 mm wave")
    # The registry's experiment of the stop (experiments.yaml tight_wave): a
    # wave tighter than the pad follows, with the same program; the servo's
    # surface_too_curved watchdog must end it before the true force reaches 7 N.
    amp, l = 0.003, 0.060
    header = f"""# A wave tighter than the pad follows (scripts/tools/make_curved_bars.py; experiments.yaml
# tight_wave): params/scenes/curved/wavy_a{amp * 1e3:g}mm_l{l * 1e3:g}mm.yaml (R {radius(amp, l) * 1e3:.1f} mm) with
# bent_bar_speed_law_careful.yaml, 40 s. The run must end with the servo's
# surface_too_curved watchdog before the true force reaches 7 N. docs/design.md,
# "Safety"."""
    with open(os.path.join(a.out, "..", "tight_wave.yaml"), "w") as fh:
        fh.write(scene_text("tight_wave", header, f"A wave tighter than the pad (A {amp * 1e3:g} mm, L {l * 1e3:g} mm, R "
                            f"{radius(amp, l) * 1e3:.1f} mm): the stop", vertices(amp, l),
                            up="..", duration=40,
                            criteria="    force_true_max_n: {max: 7.0}"))
    print("tight_wave: the careful speed law on the A 3 mm, L 60 mm wave, stopped")


if __name__ == "__main__":
    main()
