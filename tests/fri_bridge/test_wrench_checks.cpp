// The estimated wrench's frame in the simulated KRC and the bridge, the KRL
// settings the simulated KRCs read, and the day-one wrench checks
// (wrench_checks.hpp) on recordings of the simulated KRC: the KrcModel's
// measurement packets, written with fri_check's recording format and read
// back, in each frame, with the wrong frame and sign, and with a wrong load.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tactile_fri/krc_model.hpp"
#include "tactile_fri/krl_settings.hpp"
#include "tactile_fri/wrench_checks.hpp"
#include "temp_file.hpp"

using namespace tactile::fri;

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr double kG = kGravityMps2;
// estExtTcpFT travels as float32: 1e-6 relative on ~20 N
constexpr double kFloatTolN = 1e-4;

/// A pose as the pendant shows it (mm; deg, A about z, B about y, C about x).
KDL::Frame pendant(double x, double y, double z, double a, double b, double c) {
  return KDL::Frame(KDL::Rotation::RPY(c * kDeg, b * kDeg, a * kDeg), KDL::Vector(x * 1e-3, y * 1e-3, z * 1e-3));
}
const KDL::Frame kSideways = pendant(500, 0, 400, 0, 90, 180);  // flange z along base -x, flange x down
const KDL::Frame kDown = pendant(500, 0, 400, 0, 0, 180);       // flange z along base -z

/// The wrench the simulated KRC reports for a plant at `pose`, as fri_check records it.
struct SimulatedKrc {
  WrenchFrame frame = WrenchFrame::Base;  // its $STIFFNESS.FRAMETYPE
  KDL::Vector force_base = KDL::Vector::Zero();  // what presses on the arm, {g}
  double true_mass = 0.0, model_mass = 0.0;
  KDL::Vector true_com = KDL::Vector::Zero(), model_com = KDL::Vector::Zero();
  KDL::Vector tool_offset = KDL::Vector::Zero();  // a constant force in flange axes (an offset)
};

/// 50 measurements of the simulated KRC at `pose`, written as fri_check
/// --record writes them; returns the file.
std::string record(const SimulatedKrc& s, const KDL::Frame& pose) {
  KrcModelParams mp;
  mp.wrench_frame = s.frame;
  KrcModel model;
  EXPECT_TRUE(model.configure(mp).ok());
  model.reset(pose);
  PlantState plant;
  plant.pose = pose;
  const KDL::Vector g(0, 0, -kG);
  const KDL::Vector f = s.force_base + g * (s.true_mass - s.model_mass) + pose.M * s.tool_offset;
  const KDL::Vector m = (pose.M * (s.true_com * s.true_mass - s.model_com * s.model_mass)) * g;
  plant.wrench = {f.x(), f.y(), f.z(), m.x(), m.y(), m.z()};
  const std::string path = tactile::test::writeTempFile("rest.csv", "");
  FILE* out = std::fopen(path.c_str(), "w");
  writeRecordingHeader(out);
  MsrPacket msr{};
  for (int i = 0; i < 50; ++i) {
    model.setState(State::Mon, Quality::Perfect, 0x7F);
    model.holdUnlessCommanding(pose);
    model.buildMeasurement(plant, 0.001 * i, msr);
    writeRecordingLine(out, 0.001 * i, msr);
  }
  std::fclose(out);
  return path;
}

RestMean rest(const std::string& file) {
  std::vector<WrenchSample> s;
  EXPECT_TRUE(readRecording(file, s).ok());
  RestMean m;
  const tactile::ConfigResult r = restMean(file, s, m);
  EXPECT_TRUE(r.ok()) << r.message();
  return m;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += l + "\n";
  return s;
}

/// A known weight `mass` hanging on the pad at `pose`, read by a bridge configured for `configured`.
WeightResult weigh(const SimulatedKrc& krc, const KDL::Frame& pose, double mass, WrenchFrame configured,
                   double reported_mass = -1.0, int sign = 1) {
  SimulatedKrc tare = krc, loaded = krc;
  loaded.force_base = krc.force_base + KDL::Vector(0, 0, -kG) * (reported_mass < 0 ? mass : reported_mass) * sign;
  KnownWeight kw;
  kw.mass_kg = mass;
  return checkKnownWeight(rest(record(tare, pose)), rest(record(loaded, pose)), kw, configured);
}

}  // namespace

// ---- the frame ----------------------------------------------------------------

TEST(WrenchFrame, ToolAxesAreTheBaseWrenchTurnedByTheMeasuredPose) {
  const std::array<double, 6> w{1.0, 2.0, -10.0, 0.1, 0.2, 0.3};
  float ft[kCartVecDim];
  fromWrenchIn(w, WrenchFrame::Tool, kDown.M, ft);
  // kDown: flange x = base x, flange y = -base y, flange z = -base z
  const std::array<double, 6> sent = toWrench(ft);
  const std::array<double, 6> want{1.0, -2.0, 10.0, 0.1, -0.2, -0.3};
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(sent[i], want[i], 1e-6) << i;
  const std::array<double, 6> back = wrenchInBase(ft, WrenchFrame::Tool, kDown.M);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(back[i], w[i], 1e-6) << i;
  fromWrenchIn(w, WrenchFrame::Base, kDown.M, ft);
  EXPECT_EQ(wrenchInBase(ft, WrenchFrame::Base, kSideways.M), toWrench(ft));  // base: the numbers as sent
  WrenchFrame f = WrenchFrame::Base;
  EXPECT_TRUE(parseWrenchFrame("tool", f));
  EXPECT_EQ(f, WrenchFrame::Tool);
  EXPECT_FALSE(parseWrenchFrame("flange", f));
  EXPECT_STREQ(toString(WrenchFrame::Base), "base");
}

TEST(WrenchFrame, TheKrcModelSendsTheWrenchInItsStiffnessFrame) {
  for (WrenchFrame frame : {WrenchFrame::Base, WrenchFrame::Tool}) {
    SimulatedKrc s;
    s.frame = frame;
    s.force_base = KDL::Vector(0, 0, -19.6133);
    const RestMean m = rest(record(s, kSideways));
    // kSideways: flange x points down (base -z), so a force along base -z is along flange +x
    const KDL::Vector want = frame == WrenchFrame::Base ? KDL::Vector(0, 0, -19.6133) : KDL::Vector(19.6133, 0, 0);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(m.w[static_cast<std::size_t>(i)], want(i), kFloatTolN) << toString(frame);
  }
}

// ---- the KRL settings the simulated KRCs read --------------------------------

namespace {
std::string krcDir() { return std::string(KRC_DIR); }
std::string slurp(const std::string& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
/// A copy of krc/TactileServo.src and .dat with one replacement in the .src.
std::string krlCopy(const std::string& from, const std::string& to) {
  std::string src = slurp(krcDir() + "/TactileServo.src");
  const std::size_t at = src.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) src.replace(at, from.size(), to);
  const std::string path = tactile::test::writeTempFile("TactileServo.src", src);
  std::ofstream(path.substr(0, path.size() - 4) + ".dat") << slurp(krcDir() + "/TactileServo.dat");
  return path;
}
}  // namespace

TEST(KrlSettings, TheShippedProgramGivesBaseAxesAndThePadsLoad) {
  KrlSettings s;
  const tactile::ConfigResult r = readKrlSettings(krcDir() + "/TactileServo.src", s);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(s.wrench_frame, WrenchFrame::Base);
  EXPECT_DOUBLE_EQ(s.load_mass_kg, 0.2);  // TS_PAD_LOAD M 0.2 = wts0614.yaml pad_mass_kg
  EXPECT_DOUBLE_EQ(s.load_com_m[2], 0.02);
}

TEST(KrlSettings, FrameTypeToolGivesToolAxesAndOtherValuesAreNamed) {
  KrlSettings s;
  tactile::ConfigResult r = readKrlSettings(krlCopy("$STIFFNESS.FRAMETYPE = #BASE", "$STIFFNESS.FRAMETYPE = #TOOL"), s);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(s.wrench_frame, WrenchFrame::Tool);
  r = readKrlSettings(krlCopy("$STIFFNESS.FRAMETYPE = #BASE", "$STIFFNESS.FRAMETYPE = #TCP"), s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("$STIFFNESS.FRAMETYPE = #TCP"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("#BASE"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("TactileServo.src:"), std::string::npos) << r.message();  // file:line
  r = readKrlSettings(krlCopy("$STIFFNESS.FRAMETYPE = #BASE", "; no frame type"), s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("no $STIFFNESS.FRAMETYPE before friStart"), std::string::npos) << r.message();
  r = readKrlSettings(krlCopy("$LOAD = TS_PAD_LOAD", "$LOAD = OTHER_LOAD"), s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("no DECL LOAD OTHER_LOAD"), std::string::npos) << r.message();
}

// The $STIFFNESS limits come from the same program: MAXFORCE kept in N / N m,
// CPMAXDELTA converted from mm / deg to m / rad; a missing or malformed one is
// an error naming the file and line.
TEST(KrlSettings, StiffnessLimitsFromTheProgram) {
  KrlSettings s;
  tactile::ConfigResult r = readKrlSettings(krcDir() + "/TactileServo.src", s);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_DOUBLE_EQ(s.limits.max_force[2], 20.0);  // TactileServo.src: MAXFORCE Z 20.0
  EXPECT_DOUBLE_EQ(s.limits.max_force[3], 2.0);
  EXPECT_DOUBLE_EQ(s.limits.cp_max_delta[0], 0.015);  // CPMAXDELTA X 15.0 mm
  EXPECT_NEAR(s.limits.cp_max_delta[5], 5.0 * kDeg, 1e-12);
  r = readKrlSettings(krlCopy("$STIFFNESS.CPMAXDELTA =", "; $STIFFNESS.CPMAXDELTA ="), s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("no $STIFFNESS.CPMAXDELTA assignment before friOpen"), std::string::npos) << r.message();
  r = readKrlSettings(krlCopy(", C 2.0}", "}"), s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("TactileServo.src:"), std::string::npos) << r.message();  // file:line
  EXPECT_NE(r.message().find("$STIFFNESS.MAXFORCE: component C missing"), std::string::npos) << r.message();
  r = readKrlSettings(krlCopy("Z 20.0,", "Z 0.0,"), s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("$STIFFNESS.MAXFORCE: component Z must be > 0"), std::string::npos) << r.message();
}

// ---- the known weight ---------------------------------------------------------

TEST(KnownWeight, EachFrameAndSignGetsItsVerdict) {
  struct Case {
    WrenchFrame krc, configured;
    int sign;
    WeightVerdict want;
  };
  const Case cases[] = {
      {WrenchFrame::Base, WrenchFrame::Base, 1, WeightVerdict::Correct},
      {WrenchFrame::Tool, WrenchFrame::Tool, 1, WeightVerdict::Correct},
      {WrenchFrame::Tool, WrenchFrame::Base, 1, WeightVerdict::WrongFrame},
      {WrenchFrame::Base, WrenchFrame::Tool, 1, WeightVerdict::WrongFrame},
      {WrenchFrame::Base, WrenchFrame::Base, -1, WeightVerdict::SignInverted},
      {WrenchFrame::Tool, WrenchFrame::Tool, -1, WeightVerdict::SignInverted},
      {WrenchFrame::Tool, WrenchFrame::Base, -1, WeightVerdict::WrongFrameAndSign},
  };
  for (const Case& c : cases) {
    SimulatedKrc krc;
    krc.frame = c.krc;
    krc.true_mass = 0.3, krc.model_mass = 0.2;  // a load error: the tare takes it out
    const WeightResult r = weigh(krc, kSideways, 2.0, c.configured, -1.0, c.sign);
    const std::string out = joined(r.lines);
    EXPECT_EQ(r.verdict, c.want) << toString(c.krc) << " krc, " << toString(c.configured) << " configured, sign "
                                 << c.sign << "\n" << out;
    EXPECT_EQ(r.frame, c.krc) << out;
    EXPECT_EQ(r.sign, c.sign) << out;
    EXPECT_NEAR(r.ratio, 1.0, 1e-4) << out;
  }
}

TEST(KnownWeight, TheVerdictNamesTheSettingToChange) {
  SimulatedKrc krc;
  krc.frame = WrenchFrame::Tool;
  const std::string out = joined(weigh(krc, kSideways, 2.0, WrenchFrame::Base).lines);
  EXPECT_NE(out.find("verdict: frame is tool not base"), std::string::npos) << out;
  EXPECT_NE(out.find("$STIFFNESS.FRAMETYPE = #BASE"), std::string::npos) << out;
  EXPECT_NE(out.find("fri.wrench_frame: tool"), std::string::npos) << out;
  const std::string ok = joined(weigh(SimulatedKrc{}, kSideways, 2.0, WrenchFrame::Base).lines);
  EXPECT_NE(ok.find("verdict: frame correct"), std::string::npos) << ok;
}

TEST(KnownWeight, AWrongMagnitudeIsNamed) {
  // the KRC reports 2.5 kg's force for the 2 kg weight: 25 % over, beyond the 10 % tolerance
  const WeightResult r = weigh(SimulatedKrc{}, kSideways, 2.0, WrenchFrame::Base, 2.5);
  EXPECT_EQ(r.verdict, WeightVerdict::MagnitudeOff) << joined(r.lines);
  EXPECT_NEAR(r.ratio, 1.25, 1e-4);
  // 5 % over: within tolerance
  EXPECT_EQ(weigh(SimulatedKrc{}, kSideways, 2.0, WrenchFrame::Base, 2.1).verdict, WeightVerdict::Correct);
}

TEST(KnownWeight, APoseThatDoesNotSeparateTheReadingsIsUndetermined) {
  // the flange pointing down: tool z = -base z, so "tool" reads like "base, inverted"
  SimulatedKrc krc;
  krc.frame = WrenchFrame::Tool;
  const WeightResult r = weigh(krc, kDown, 2.0, WrenchFrame::Base);
  EXPECT_EQ(r.verdict, WeightVerdict::Undetermined) << joined(r.lines);
  EXPECT_NE(joined(r.lines).find("tilt the flange"), std::string::npos) << joined(r.lines);
  // and no weight at all
  const WeightResult none = weigh(SimulatedKrc{}, kSideways, 2.0, WrenchFrame::Base, 0.0);
  EXPECT_EQ(none.verdict, WeightVerdict::Undetermined) << joined(none.lines);
}

TEST(KnownWeight, ARecordingInWhichTheArmMovedIsRefused) {
  const std::string path = tactile::test::writeTempFile("moved.csv", "");
  FILE* out = std::fopen(path.c_str(), "w");
  writeRecordingHeader(out);
  MsrPacket msr{};
  for (int i = 0; i < 10; ++i) {
    fromFrame(KDL::Frame(kDown.M, kDown.p + KDL::Vector(0.001 * i, 0, 0)), msr.data.msr_cart_pos);  // 9 mm
    writeRecordingLine(out, 0.001 * i, msr);
  }
  std::fclose(out);
  std::vector<WrenchSample> s;
  ASSERT_TRUE(readRecording(path, s).ok());
  RestMean m;
  const tactile::ConfigResult r = restMean(path, s, m);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("the arm moved 9.0 mm"), std::string::npos) << r.message();
}

// ---- the load data ------------------------------------------------------------

namespace {
/// Four orientations at rest: down, tilted 60 deg about x, about y, and turned.
const KDL::Frame kRestPoses[] = {pendant(500, 0, 400, 0, 0, 180), pendant(500, 0, 400, 0, 0, 120),
                                 pendant(500, 0, 400, 0, 60, 180), pendant(500, 0, 400, 90, 45, 150)};

LoadResult fitOn(const SimulatedKrc& krc, const LoadModel& model, WrenchFrame read_as, int poses = 4) {
  std::vector<RestMean> rests;
  for (int i = 0; i < poses; ++i) rests.push_back(rest(record(krc, kRestPoses[i])));
  return fitLoad(rests, read_as, model);
}

SimulatedKrc withLoad(double true_mass, KDL::Vector true_com) {
  SimulatedKrc s;
  s.model_mass = 0.2;
  s.model_com = KDL::Vector(0, 0, 0.02);  // TS_PAD_LOAD = wts0614.yaml's pad
  s.true_mass = true_mass;
  s.true_com = true_com;
  return s;
}
const LoadModel kModel{0.2, KDL::Vector(0, 0, 0.02)};
}  // namespace

TEST(LoadData, TheRightLoadIsOk) {
  const LoadResult r = fitOn(withLoad(0.2, KDL::Vector(0, 0, 0.02)), kModel, WrenchFrame::Base);
  EXPECT_EQ(r.verdict, LoadVerdict::Ok) << joined(r.lines);
  EXPECT_NEAR(r.dm_kg, 0.0, 1e-4);
}

TEST(LoadData, AWrongPadMassIsFoundInEachFrame) {
  for (WrenchFrame frame : {WrenchFrame::Base, WrenchFrame::Tool}) {
    SimulatedKrc krc = withLoad(0.5, KDL::Vector(0, 0, 0.02));  // 0.3 kg unmodelled
    krc.frame = frame;
    const LoadResult r = fitOn(krc, kModel, frame);
    EXPECT_EQ(r.verdict, LoadVerdict::MassOff) << joined(r.lines);
    // float32 packets: 1e-4 kg (1 mN) and 0.1 mm
    EXPECT_NEAR(r.dm_kg, 0.3, 1e-4) << toString(frame);
    EXPECT_NEAR(r.mass_kg, 0.5, 1e-4);
    EXPECT_NEAR((r.com_m - KDL::Vector(0, 0, 0.02)).Norm(), 0.0, 1e-4);
    EXPECT_NE(joined(r.lines).find("pad_mass_kg: 0.500"), std::string::npos) << joined(r.lines);
    EXPECT_NE(joined(r.lines).find("M 0.500"), std::string::npos) << joined(r.lines);
  }
}

TEST(LoadData, AWrongCentreOfMassIsFound) {
  const LoadResult r = fitOn(withLoad(0.2, KDL::Vector(0.03, -0.01, 0.05)), kModel, WrenchFrame::Base);
  EXPECT_EQ(r.verdict, LoadVerdict::ComOff) << joined(r.lines);
  EXPECT_NEAR((r.com_m - KDL::Vector(0.03, -0.01, 0.05)).Norm(), 0.0, 1e-4) << joined(r.lines);
  const LoadResult both = fitOn(withLoad(0.6, KDL::Vector(0.0, 0.02, 0.04)), kModel, WrenchFrame::Base);
  EXPECT_EQ(both.verdict, LoadVerdict::MassAndComOff) << joined(both.lines);
  EXPECT_NEAR((both.com_m - KDL::Vector(0.0, 0.02, 0.04)).Norm(), 0.0, 1e-4) << joined(both.lines);
}

TEST(LoadData, AConstantOffsetIsFittedApartFromTheLoad) {
  SimulatedKrc krc = withLoad(0.5, KDL::Vector(0, 0, 0.02));
  krc.tool_offset = KDL::Vector(1.5, -0.5, 2.0);  // N, in flange axes
  const LoadResult r = fitOn(krc, kModel, WrenchFrame::Base);
  EXPECT_EQ(r.verdict, LoadVerdict::MassOff) << joined(r.lines);
  EXPECT_NEAR(r.dm_kg, 0.3, 1e-4);
  EXPECT_NEAR((r.bias_f - KDL::Vector(1.5, -0.5, 2.0)).Norm(), 0.0, 1e-3);
}

TEST(LoadData, TooFewOrTooAlikeOrientationsAreUndetermined) {
  const SimulatedKrc krc = withLoad(0.5, KDL::Vector(0, 0, 0.02));
  EXPECT_EQ(fitOn(krc, kModel, WrenchFrame::Base, 2).verdict, LoadVerdict::Undetermined);
  // only A6 turned with the flange pointing down: gravity is the same in flange axes
  std::vector<RestMean> rests;
  for (double a : {0.0, 60.0, 120.0}) rests.push_back(rest(record(krc, pendant(500, 0, 400, a, 0, 180))));
  const LoadResult r = fitLoad(rests, WrenchFrame::Base, kModel);
  EXPECT_EQ(r.verdict, LoadVerdict::Undetermined) << joined(r.lines);
  EXPECT_NE(joined(r.lines).find("too alike"), std::string::npos) << joined(r.lines);
}

TEST(KnownWeight, APushAlongThePadNormalIsGivenInToolAxes) {
  // 15 N pressed on the pad's face along the flange's -z (the pad facing +z
  // of the flange), the flange tilted: KnownWeight::dir_in_tool
  const KDL::Frame tilted = pendant(500, 0, 400, 30, 45, 150);
  SimulatedKrc tare, pushed;
  pushed.force_base = tilted.M * KDL::Vector(0, 0, -15.0);
  KnownWeight kw;
  kw.mass_kg = 15.0 / kG;
  kw.dir = KDL::Vector(0, 0, -1);
  kw.dir_in_tool = true;
  const WeightResult r = checkKnownWeight(rest(record(tare, tilted)), rest(record(pushed, tilted)), kw, WrenchFrame::Base);
  EXPECT_EQ(r.verdict, WeightVerdict::Correct) << joined(r.lines);
  EXPECT_NEAR((r.expected_base - pushed.force_base).Norm(), 0.0, kFloatTolN);  // the pose as float32
  // the same push read as a weight along gravity does not fit
  kw.dir_in_tool = false;
  const WeightResult g = checkKnownWeight(rest(record(tare, tilted)), rest(record(pushed, tilted)), kw, WrenchFrame::Base);
  EXPECT_NE(g.verdict, WeightVerdict::Correct) << joined(g.lines);
}

TEST(KnownWeight, AnUnreadableRecordingNamesItsFileAndLine) {
  std::vector<WrenchSample> s;
  const std::string bad = tactile::test::writeTempFile(
      "bad.csv", "t_s,state,quality,r11,r12,r13,x,r21,r22,r23,y,r31,r32,r33,z,fx,fy,fz,tx,ty,tz\n0.0,1,3,1,0,0\n");
  tactile::ConfigResult r = readRecording(bad, s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("bad.csv:2: expected 21 numbers"), std::string::npos) << r.message();
  const std::string empty = tactile::test::writeTempFile("empty.csv", "t_s,state\n");
  r = readRecording(empty, s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("no measurement"), std::string::npos) << r.message();
  r = readRecording("/nonexistent/rec.csv", s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("/nonexistent/rec.csv: cannot read"), std::string::npos) << r.message();
}
