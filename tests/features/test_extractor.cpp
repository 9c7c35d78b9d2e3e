#include <gtest/gtest.h>
#include "tactile_features/extractor.hpp"
TEST(Extractor, Smoke) {
  tactile::FeatureExtractor ex;
  ASSERT_TRUE(ex.configure({}).ok());
}
