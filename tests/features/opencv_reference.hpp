// An independent implementation of the tactile features with OpenCV, used as
// the reference in test_opencv_reference.cpp and as the "alternative" in
// bench_features.cpp. It shares no code with tactile::FeatureExtractor:
//   moments      cv::moments (non-binary) on the CV_64F pressure image
//   CoC          cv::threshold(THRESH_BINARY) + cv::moments(binaryImage = true)
//   Otsu         cv::threshold(THRESH_BINARY | THRESH_OTSU) on a CV_8U image
//   PCA          cv::eigen on the 2x2 covariance [mu20 mu11; mu11 mu02] / m00
// Pixel (row r, col c) sits at OpenCV coordinates (x = c, y = r); the {s}
// position is ((c - (cols-1)/2) * pitch, (r - (rows-1)/2) * pitch).
#pragma once

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "tactile_types/types.hpp"

namespace tactile {
namespace test {

struct ReferenceFeatures {
  double cop_x = 0, cop_y = 0, coc_x = 0, coc_y = 0, dzmp_x = 0, dzmp_y = 0;
  double lambda1 = 0, lambda2 = 0, alpha_z = 0, force = 0;
  int area = 0;
};

/// `otsu8u`: when non-null, the frame is taken as 8-bit levels (force = level *
/// step) and Otsu's threshold is computed by OpenCV on that CV_8U image.
inline ReferenceFeatures referenceFeatures(const TactileFrame& frame, double pitch, double threshold,
                                           const cv::Mat* otsu8u = nullptr, double step = 1.0) {
  ReferenceFeatures out;
  const int rows = frame.rows, cols = frame.cols;
  cv::Mat img(rows, cols, CV_64F);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) img.at<double>(r, c) = std::max(0.0, frame.at(r, c));
  const cv::Moments m = cv::moments(img, false);
  if (m.m00 <= 0) return out;
  const double cx0 = (cols - 1) / 2.0, cy0 = (rows - 1) / 2.0;
  out.force = m.m00;
  out.cop_x = (m.m10 / m.m00 - cx0) * pitch;
  out.cop_y = (m.m01 / m.m00 - cy0) * pitch;

  cv::Mat bin;
  if (otsu8u) {
    cv::Mat b8;
    const double t = cv::threshold(*otsu8u, b8, 0, 1, cv::THRESH_BINARY | cv::THRESH_OTSU);
    (void)t;
    b8.convertTo(bin, CV_64F);
    (void)step;
  } else {
    cv::threshold(img, bin, threshold, 1.0, cv::THRESH_BINARY);
  }
  const cv::Moments mb = cv::moments(bin, true);
  out.area = static_cast<int>(std::lround(mb.m00));
  if (mb.m00 > 0) {
    out.coc_x = (mb.m10 / mb.m00 - cx0) * pitch;
    out.coc_y = (mb.m01 / mb.m00 - cy0) * pitch;
  } else {
    out.coc_x = out.cop_x;
    out.coc_y = out.cop_y;
  }
  out.dzmp_x = out.cop_y - out.coc_y;
  out.dzmp_y = out.cop_x - out.coc_x;

  cv::Matx22d cov(m.mu20 / m.m00 * pitch * pitch, m.mu11 / m.m00 * pitch * pitch, m.mu11 / m.m00 * pitch * pitch,
                  m.mu02 / m.m00 * pitch * pitch);
  cv::Mat evals, evecs;
  cv::eigen(cv::Mat(cov), evals, evecs);  // descending eigenvalues, eigenvectors in rows
  out.lambda1 = evals.at<double>(0);
  out.lambda2 = std::max(0.0, evals.at<double>(1));
  double a = std::atan2(evecs.at<double>(0, 1), evecs.at<double>(0, 0));  // Eq. B.5
  while (a > kPi / 2) a -= kPi;
  while (a <= -kPi / 2) a += kPi;
  out.alpha_z = a;
  return out;
}

}  // namespace test
}  // namespace tactile
