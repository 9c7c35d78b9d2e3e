// tactile::FeatureComponent in-process: SlaveActivity, frames through its ports,
// update() by hand, outputs compared with the cores run directly.
#include <gtest/gtest.h>

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/os/main.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

#include "alloc_counter.hpp"
#include "support/raw_from_forces.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_features/extractor.hpp"
#include "tactile_features_rtt/feature_component.hpp"
#include "tactile_sim_contact/elastic_pad.hpp"
#include "support/rtt_environment.hpp"
#include "temp_file.hpp"
#include "tactile_types_rtt/atomic_attribute.hpp"

namespace {

using tactile::ContactFeatures;
using tactile::FeatureStatus;
using tactile::RawTactileFrame;
using tactile::TactileFrame;

const auto* const env =
    ::testing::AddGlobalTestEnvironment(new tactile::test::RttEnvironment(tactile::test::Clock::System));

// The one sensor parameter file (the headless runner reads it too).
const std::string kParamFile = TACTILE_DEPLOYMENTS_DIR "/../params/sensors/wts0614.yaml";

std::string writeTemp(const std::string& name, const std::string& text) {
  return tactile::test::writeTempFile(name, text);
}

// The calibration of kParamFile (to turn synthetic forces into raw counts).
const tactile::Calibration& fileCalibration() {
  static const tactile::Calibration cal = [] {
    tactile::FeatureParams fp;
    tactile::CalibrationParams cp;
    tactile::Calibration c;
    EXPECT_TRUE(tactile::loadSensorParamFile(kParamFile, fp, cp).ok());
    EXPECT_TRUE(c.configure(cp).ok());
    return c;
  }();
  return cal;
}

// An edge (length > 0) or disc contact on the elastic pad, as raw counts that
// the calibration of kParamFile maps back to the pad's forces.
RawTactileFrame pressed(double cx, double cy, double length, double angle, double depth, uint32_t seq) {
  tactile::sim::PadGeometry g;
  TactileFrame f;
  const double ux = std::cos(angle), uy = std::sin(angle), r = 0.003;
  tactile::sim::integratePad(g, [&](double x, double y) {
    const double dx = x - cx, dy = y - cy;
    const double t = std::max(-length / 2, std::min(length / 2, dx * ux + dy * uy));
    const double ex = dx - t * ux, ey = dy - t * uy;
    return depth * (1.0 - (ex * ex + ey * ey) / (r * r));
  }, f);
  RawTactileFrame raw;
  tactile::test::rawFromForces(fileCalibration(), f, raw);
  raw.seq = seq;
  raw.time_s = seq / 140.0;  // the WTS frame rate (the features average firing rates over 0.1 s)
  return raw;
}

void expectSame(const ContactFeatures& a, const ContactFeatures& b) {
  // Same code, same input: bit-identical results expected (tolerance 0).
  EXPECT_EQ(a.seq, b.seq);
  EXPECT_EQ(a.time_s, b.time_s);
  EXPECT_EQ(a.cop_x, b.cop_x);
  EXPECT_EQ(a.cop_y, b.cop_y);
  EXPECT_EQ(a.coc_x, b.coc_x);
  EXPECT_EQ(a.coc_y, b.coc_y);
  EXPECT_EQ(a.dzmp_x, b.dzmp_x);
  EXPECT_EQ(a.dzmp_y, b.dzmp_y);
  EXPECT_EQ(a.alpha_z, b.alpha_z);
  EXPECT_EQ(a.force, b.force);
  EXPECT_EQ(a.d_z, b.d_z);
  EXPECT_EQ(a.lambda1, b.lambda1);
  EXPECT_EQ(a.lambda2, b.lambda2);
  EXPECT_EQ(a.max_taxel, b.max_taxel);
  EXPECT_EQ(a.area, b.area);
  EXPECT_EQ(a.contact, b.contact);
  EXPECT_EQ(a.status, b.status);
}

// The component plus a source and a sink task, connected, on slave activities.
struct Rig {
  tactile::FeatureComponent comp{"features"};
  RTT::OutputPort<RawTactileFrame> raw_out{"raw_out"};
  RTT::OutputPort<TactileFrame> frame_out{"frame_out"};
  RTT::InputPort<ContactFeatures> features_in{"features_in"};
  RTT::InputPort<TactileFrame> calibrated_in{"calibrated_in"};
  RTT::TaskContext io{"io"};  // declared last: destroyed before the ports it holds

  explicit Rig(const std::string& param_file) {
    comp.setActivity(new RTT::extras::SlaveActivity());
    io.ports()->addPort(raw_out);
    io.ports()->addPort(frame_out);
    io.ports()->addPort(features_in);
    io.ports()->addPort(calibrated_in);
    comp.properties()->getPropertyType<std::string>("param_file")->set(param_file);
    EXPECT_TRUE(raw_out.connectTo(comp.ports()->getPort("raw_frame")));
    EXPECT_TRUE(frame_out.connectTo(comp.ports()->getPort("frame")));
    EXPECT_TRUE(comp.ports()->getPort("features")->connectTo(&features_in));
    EXPECT_TRUE(comp.ports()->getPort("calibrated_frame")->connectTo(&calibrated_in));
    RawTactileFrame raw_sample;
    TactileFrame frame_sample;
    raw_out.setDataSample(raw_sample);
    frame_out.setDataSample(frame_sample);
  }
  int frames() { return comp.provides()->getAttribute("frames") ? tactile::readAttribute<int>(*comp.provides(), "frames") : -1; }
};

struct Cores {
  tactile::Calibration cal;
  tactile::FeatureExtractor ex;
  Cores() {
    tactile::FeatureParams fp;
    tactile::CalibrationParams cp;
    const tactile::ConfigResult r = tactile::loadSensorParamFile(kParamFile, fp, cp);
    EXPECT_TRUE(r.ok()) << r.message();
    EXPECT_TRUE(cal.configure(cp).ok());
    fp.taxel_noise = cal.noiseForce(fp.contact_threshold);  // as SensorStage::configure
    EXPECT_TRUE(ex.configure(fp).ok());
  }
};

TEST(FeatureComponent, InterfaceIsDeclaredAndDocumented) {
  tactile::FeatureComponent c("f");
  for (const char* port : {"raw_frame", "frame", "features", "calibrated_frame"}) {
    ASSERT_NE(c.ports()->getPort(port), nullptr) << port;
    EXPECT_FALSE(c.ports()->getPort(port)->getDescription().empty()) << port;
  }
  EXPECT_EQ(c.ports()->getPort("features")->getTypeInfo()->getTypeName(),
            RTT::internal::DataSourceTypeInfo<ContactFeatures>::getTypeInfo()->getTypeName());
  ASSERT_NE(c.properties()->getProperty("param_file"), nullptr);
  EXPECT_FALSE(c.properties()->getProperty("param_file")->getDescription().empty());
  for (const char* op : {"tare", "reload", "lastError"}) {
    EXPECT_TRUE(c.provides()->hasOperation(op)) << op;
    EXPECT_FALSE(c.provides()->getDescription(op).empty()) << op;
  }
}

TEST(FeatureComponent, RawFramesGiveTheCoresFeatures) {
  Rig rig(kParamFile);
  ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
  ASSERT_TRUE(rig.comp.start());
  Cores cores;
  // A contact that moves and turns from a disc into an edge: history
  // (hysteresis of the contact type and of alpha_z) must be kept identically.
  for (uint32_t k = 0; k < 40; ++k) {
    const double s = k / 39.0;
    const RawTactileFrame raw = pressed(-0.01 + 0.02 * s, 0.002 * s, 0.025 * s, 0.3 + 1.4 * s, 0.001 + 0.002 * s, k);
    rig.raw_out.write(raw);
    ASSERT_TRUE(rig.comp.update());
    ContactFeatures got;
    ASSERT_EQ(rig.features_in.read(got), RTT::NewData) << k;
    TactileFrame cal_got;
    ASSERT_EQ(rig.calibrated_in.read(cal_got), RTT::NewData) << k;
    TactileFrame frame;
    cores.cal.step(raw, frame);
    ContactFeatures want;
    cores.ex.step(frame, want);
    expectSame(got, want);
    for (int i = 0; i < frame.size(); ++i) ASSERT_EQ(cal_got.force[static_cast<std::size_t>(i)], frame.force[static_cast<std::size_t>(i)]);
  }
  EXPECT_EQ(rig.frames(), 40);
  // The run covered the interesting cases (otherwise this test proves little).
  ContactFeatures last;
  rig.features_in.read(last, true);
  EXPECT_EQ(last.contact, tactile::ContactType::Edge);
  EXPECT_EQ(last.status, FeatureStatus::Ok);
}

TEST(FeatureComponent, CalibratedFramePortGivesTheExtractorFeatures) {
  Rig rig(kParamFile);
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  Cores cores;
  TactileFrame f;
  cores.cal.step(pressed(0.004, -0.002, 0.0, 0.0, 0.003, 5), f);
  rig.frame_out.write(f);
  ASSERT_TRUE(rig.comp.update());
  ContactFeatures got, want;
  ASSERT_EQ(rig.features_in.read(got), RTT::NewData);
  cores.ex.step(f, want);
  expectSame(got, want);
  EXPECT_EQ(got.contact, tactile::ContactType::Point);
  EXPECT_NEAR(got.cop_x, 0.004, 0.0005);  // pad discretisation at 3.4 mm pitch; disc centred at 4 mm
}

TEST(FeatureComponent, NoNewDataWritesNothing) {
  Rig rig(kParamFile);
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  ASSERT_TRUE(rig.comp.update());
  ContactFeatures got;
  EXPECT_EQ(rig.features_in.read(got), RTT::NoData);
  rig.raw_out.write(pressed(0, 0, 0, 0, 0.002, 1));
  ASSERT_TRUE(rig.comp.update());
  EXPECT_EQ(rig.features_in.read(got), RTT::NewData);
  ASSERT_TRUE(rig.comp.update());  // nothing new
  EXPECT_EQ(rig.features_in.read(got), RTT::OldData);
  EXPECT_EQ(rig.frames(), 1);
}

TEST(FeatureComponent, MalformedFramesGiveAStatusNotACrash) {
  Rig rig(kParamFile);
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  RawTactileFrame wrong = pressed(0, 0, 0, 0, 0.002, 3);
  wrong.rows = 60000;  // garbage size
  rig.raw_out.write(wrong);
  ASSERT_TRUE(rig.comp.update());
  ContactFeatures got;
  ASSERT_EQ(rig.features_in.read(got), RTT::NewData);
  EXPECT_EQ(got.status, FeatureStatus::BadDimensions);
  EXPECT_EQ(got.seq, 3u);
  EXPECT_EQ(got.force, 0.0);

  TactileFrame nan_frame;
  nan_frame.force[7] = std::numeric_limits<double>::quiet_NaN();
  rig.frame_out.write(nan_frame);
  ASSERT_TRUE(rig.comp.update());
  ASSERT_EQ(rig.features_in.read(got), RTT::NewData);
  EXPECT_EQ(got.status, FeatureStatus::InvalidInput);
  EXPECT_TRUE(std::isfinite(got.cop_x) && std::isfinite(got.force) && std::isfinite(got.alpha_z));
}

TEST(FeatureComponent, TareZeroesTheNextFrameAndALoadedTareIsRejected) {
  Rig rig(kParamFile);
  EXPECT_FALSE(rig.comp.tare());  // not configured yet
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  ContactFeatures got;
  // A tare under load (offsets beyond calibration.max_tare) is rejected: the
  // load stays measured and the status says so.
  const RawTactileFrame loaded = pressed(0.0, 0.0, 0.02, 0.3, 0.003, 1);
  rig.raw_out.write(loaded);
  ASSERT_TRUE(rig.comp.update());
  ASSERT_EQ(rig.features_in.read(got), RTT::NewData);
  EXPECT_NE(got.status, FeatureStatus::NoContact);
  const double loaded_force = got.force;
  EXPECT_TRUE(rig.comp.tare());
  rig.raw_out.write(loaded);
  ASSERT_TRUE(rig.comp.update());
  ASSERT_EQ(rig.features_in.read(got), RTT::NewData);
  EXPECT_EQ(got.status, FeatureStatus::TareRejected);
  EXPECT_EQ(got.force, loaded_force);
  // A no-load offset (300 counts everywhere, below max_tare) is taken: the
  // same frame then reads zero.
  RawTactileFrame offset = loaded;
  for (int i = 0; i < offset.rows * offset.cols; ++i) offset.counts[static_cast<std::size_t>(i)] = 300;
  EXPECT_TRUE(rig.comp.tare());
  rig.raw_out.write(offset);
  ASSERT_TRUE(rig.comp.update());
  ASSERT_EQ(rig.features_in.read(got), RTT::NewData);
  EXPECT_EQ(got.status, FeatureStatus::NoContact);
  EXPECT_EQ(got.force, 0.0);
}

TEST(FeatureComponent, BadParamFileMakesConfigureFail) {
  {
    Rig rig(TACTILE_DEPLOYMENTS_DIR "/params/does_not_exist.yaml");
    EXPECT_FALSE(rig.comp.configure());
    EXPECT_NE(rig.comp.lastError().find("does_not_exist.yaml"), std::string::npos) << rig.comp.lastError();
    EXPECT_FALSE(rig.comp.start());
  }
  {
    Rig rig("");
    EXPECT_FALSE(rig.comp.configure());
    EXPECT_NE(rig.comp.lastError().find("param_file"), std::string::npos) << rig.comp.lastError();
  }
  {
    Rig rig(writeTemp("bad_pitch.yaml", "features:\n  pitch: -0.001\n"));
    EXPECT_FALSE(rig.comp.configure());
    EXPECT_NE(rig.comp.lastError().find("pitch"), std::string::npos) << rig.comp.lastError();
  }
  {
    Rig rig(writeTemp("typo.yaml", "features:\n  treshold: 0.3\n"));
    EXPECT_FALSE(rig.comp.configure());
    EXPECT_NE(rig.comp.lastError().find("treshold"), std::string::npos) << rig.comp.lastError();
  }
  {
    Rig rig(writeTemp("bad_cal.yaml", "calibration:\n  full_scale: 9000\n"));
    EXPECT_FALSE(rig.comp.configure());
    EXPECT_NE(rig.comp.lastError().find("calibration.full_scale"), std::string::npos) << rig.comp.lastError();
  }
}

TEST(FeatureComponent, ReloadOnlyWhenStopped) {
  const std::string file = writeTemp("reload.yaml", "features:\n  threshold: 0.2\n");
  Rig rig(file);
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  EXPECT_FALSE(rig.comp.reload());
  ASSERT_TRUE(rig.comp.stop());
  std::ofstream(file) << "features:\n  pitch: 0\n";
  EXPECT_FALSE(rig.comp.reload());
  EXPECT_NE(rig.comp.lastError().find("pitch"), std::string::npos);
  std::ofstream(file) << "features:\n  threshold: 0.3\n";
  EXPECT_TRUE(rig.comp.reload()) << rig.comp.lastError();
  EXPECT_TRUE(rig.comp.lastError().empty());
}

TEST(FeatureComponent, UpdateCycleDoesNotAllocate) {
  Rig rig(kParamFile);
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  RawTactileFrame a = pressed(0.003, 0.001, 0.02, 0.5, 0.002, 0);
  TactileFrame f;
  ContactFeatures got;
  rig.raw_out.write(a);  // warm-up: first write/read through every connection
  rig.comp.update();
  rig.features_in.read(got);
  rig.calibrated_in.read(f);
  int received = 0;
  tactile::test::AllocationScope scope;
  for (uint32_t k = 1; k <= 200; ++k) {
    a.seq = k;
    rig.raw_out.write(a);
    rig.comp.update();
    if (rig.features_in.read(got, false) == RTT::NewData && got.seq == k) ++received;
    rig.calibrated_in.read(f, false);
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_EQ(received, 200);
}

}  // namespace
