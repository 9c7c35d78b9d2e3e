// Generates the sample recording shipped in data/: frames synthesised from
// analytic contacts on the elastic-foundation pad (elastic_pad.hpp), with a
// little seeded noise and the WTS firing threshold (taxels below 0.2 N read 0).
//
//   make_sample_recording OUT.csv TRUTH.csv
//
// OUT.csv: one frame per line, 84 forces (N), row-major: the tactile_features
// input format. TRUTH.csv: per frame the analytic contact that produced it.
// Script (100 Hz, 4 s):
//   0.0-1.0 s  a sphere (R 10 mm) presses in at the centre (depth 0 -> 2.5 mm)
//   1.0-2.0 s  the sphere slides along x_s from -15 mm to +15 mm
//   2.0-3.0 s  an edge (depth 3 mm) rotates from -60 deg to +60 deg
//   3.0-4.0 s  an edge along x_s with a load gradient from -0.02 to +0.02 m/m
#include <cmath>
#include <cstdio>
#include <random>

#include "tactile_sim_contact/elastic_pad.hpp"

using namespace tactile;

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: make_sample_recording OUT.csv TRUTH.csv\n");
    return 2;
  }
  FILE* out = std::fopen(argv[1], "w");
  FILE* truth = std::fopen(argv[2], "w");
  if (!out || !truth) {
    std::fprintf(stderr, "make_sample_recording: cannot write output files\n");
    return 2;
  }
  std::fprintf(truth, "t,kind,x0,y0,angle,depth,slope,force_true,cop_x_true,cop_y_true\n");
  std::mt19937 rng(2020);
  std::normal_distribution<double> noise(0.0, 0.01);
  sim::PadGeometry g;
  g.subsamples = 8;
  const double deg = kPi / 180;
  for (int k = 0; k < 400; ++k) {
    const double t = k / 100.0;
    const double s = std::fmod(t, 1.0);
    TactileFrame f;
    sim::PadTruth tr;
    const char* kind;
    double x0 = 0, y0 = 0, angle = 0, depth = 0, slope = 0;
    if (t < 1.0) {
      kind = "sphere";
      depth = 0.0025 * s;
      sim::integratePad(g, sim::SphereIndent{x0, y0, 0.010, depth}, f, &tr);
    } else if (t < 2.0) {
      kind = "sphere";
      depth = 0.0025;
      x0 = -0.015 + 0.030 * s;
      sim::integratePad(g, sim::SphereIndent{x0, y0, 0.010, depth}, f, &tr);
    } else if (t < 3.0) {
      kind = "edge";
      depth = 0.003;
      angle = (-60 + 120 * s) * deg;
      sim::integratePad(g, sim::EdgeIndent{x0, y0, angle, depth, 0.0015, 1.0}, f, &tr);
    } else {
      kind = "edge";
      depth = 0.003;
      slope = -0.02 + 0.04 * s;
      sim::integratePad(g, sim::EdgeIndent{x0, y0, 0.0, depth, 0.0015, 1.0, slope}, f, &tr);
    }
    for (int i = 0; i < f.size(); ++i) {
      double& v = f.force[static_cast<std::size_t>(i)];
      v = v + noise(rng);
      if (v < 0.2) v = 0.0;  // WTS firing threshold (App. A, Fig. A.15)
      std::fprintf(out, i ? ",%.4f" : "%.4f", v);
    }
    std::fprintf(out, "\n");
    std::fprintf(truth, "%.2f,%s,%.6f,%.6f,%.6f,%.6f,%.4f,%.6f,%.6f,%.6f\n", t, kind, x0, y0, angle, depth, slope,
                 tr.force, tr.cop_x, tr.cop_y);
  }
  std::fclose(out);
  std::fclose(truth);
  return 0;
}
