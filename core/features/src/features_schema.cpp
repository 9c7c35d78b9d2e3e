#include "tactile_features/features_schema.hpp"

namespace tactile {

const schema::Block<FeatureParams>& featuresSchema() {
  using S = FeatureParams;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "features",
      "the taxel layout and the feature extraction (FeatureExtractor, extractor.hpp; Sec. 3, App. B)",
      {F::whole("rows", "", "[1, 16]", TACTILE_SCHEMA_REF(S, rows), "taxel rows (y_s)"),
       F::whole("cols", "", "[1, 32]", TACTILE_SCHEMA_REF(S, cols), "taxel columns (x_s)"),
       F::num("pitch", "m", "> 0", TACTILE_SCHEMA_REF(S, pitch), "the taxel pitch"),
       F::num("c_z", "m/N", ">= 0", TACTILE_SCHEMA_REF(S, c_z), "the pad's compliance: d_z = C_z f (Eq. 2)"),
       F::custom("threshold", "N", ">= 0, or otsu", "0.2",
                 "the binarisation behind the centre of contact (Sec. 3.2): fixed, or Otsu's per frame"),
       F::num("contact_threshold", "N", ">= 0", TACTILE_SCHEMA_REF(S, contact_threshold),
              "a taxel above it is in contact (the WTS's firing threshold, App. A)"),
       F::num("edge_ratio", "", ">= 1", TACTILE_SCHEMA_REF(S, edge_ratio),
              "lambda1 / lambda2 at which a point contact becomes an edge (Eq. 5)"),
       F::num("edge_ratio_exit", "", "[1, edge_ratio]", TACTILE_SCHEMA_REF(S, edge_ratio_exit),
              "the ratio below which an edge becomes a point again (hysteresis)"),
       F::num("edge_min_length", "m", ">= 0", TACTILE_SCHEMA_REF(S, edge_min_length),
              "an edge is at least this long (sqrt(12 lambda1)): two taxels are not an edge"),
       F::deg("alpha_hysteresis_deg", "deg", "[0, 45]", TACTILE_SCHEMA_REF(S, alpha_hysteresis),
              "the branch hysteresis of alpha_z near +-90 deg"),
       F::num("isotropy_tol", "", "[0, 1)", TACTILE_SCHEMA_REF(S, isotropy_tol),
              "the relative eigenvalue gap below which alpha_z is held"),
       F::num("alpha_max_sigma", "rad", "> 0", TACTILE_SCHEMA_REF(S, alpha_max_sigma),
              "alpha_z is defined while its noise (from calibration.noise_counts) is at most this"),
       F::num("censor_tau", "s", ">= 0", TACTILE_SCHEMA_REF(S, censor_tau),
              "the firing rate's time constant behind the sub-threshold force estimate (0: off)"),
       F::num("censor_min_rate", "", "[0.01, 0.99]", TACTILE_SCHEMA_REF(S, censor_min_rate),
              "a silent taxel firing at least this often gets its maximum-likelihood load"),
       F::whole("region_gap", "taxels", "[0, 4]", TACTILE_SCHEMA_REF(S, region_gap),
                "silent taxels that do not split a contact region"),
       F::num("region_min_force", "N", "> 0", TACTILE_SCHEMA_REF(S, region_min_force),
              "a region this strong is a separate contact (two: multiple)"),
       F::num("region_min_rate", "", "[0.00135, 0.99]", TACTILE_SCHEMA_REF(S, region_min_rate),
              "a silent taxel joins regions while it fires this often"),
       F::num("max_taxel_force", "N", "> 0", TACTILE_SCHEMA_REF(S, max_taxel_force),
              "a finite taxel value beyond this is not a reading (status OutOfRange)")}};
  return b;
}

const schema::Block<CalibrationFile>& calibrationSchema() {
  using S = CalibrationFile;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "calibration",
      "counts to newtons per taxel (Calibration, calibration.hpp; App. A): f = c0 + c1 n + c2 n^2 + c3 n^3 of "
      "the tared count n; written by tactile_calibrate",
      {F::whole("full_scale", "counts", "[1, 4095]", TACTILE_SCHEMA_REF(S, full_scale),
                "the count at which a taxel saturates (12-bit)"),
       F::whole("max_tare", "counts", "[0, full_scale]", TACTILE_SCHEMA_REF(S, max_tare),
                "the largest tare offset accepted; a larger one is refused and the previous tare kept"),
       F::num("noise_counts", "counts", "[0, 1000]", TACTILE_SCHEMA_REF(S, noise_counts),
              "the sensor's count noise, 1 sigma (the features' alpha_z test, the sub-threshold estimate)"),
       F::custom("coeffs", "N per count^k", "1 to 4 finite numbers (c0 ... c3)", "0, 0.002, 0, 0",
                 "the polynomial of every taxel not given otherwise"),
       F::custom("border_coeffs", "N per count^k", "1 to 4 finite numbers", "none: coeffs",
                 "the polynomial of the outer ring's taxels"),
       F::custom("taxels", "N per count^k", "rows x cols lists of 1 to 4 finite numbers, row-major",
                 "none", "one polynomial per taxel; replaces coeffs and border_coeffs")}};
  return b;
}

std::string sensorSchemaMarkdown() {
  return schema::markdownSection(featuresSchema()) + "\n" + schema::markdownSection(calibrationSchema());
}

}  // namespace tactile
