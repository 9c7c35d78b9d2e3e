// The tactile typekit, loaded in-process the way the deployer loads it (from
// <build>/lib/orocos/<target>/tactile/types through RTT's PluginLoader).
#include <gtest/gtest.h>

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/Property.hpp>
#include <rtt/PropertyBag.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/internal/DataSources.hpp>
#include <rtt/os/main.h>
#include <rtt/plugin/PluginLoader.hpp>
#include <rtt/types/Operators.hpp>
#include <rtt/types/PropertyDecomposition.hpp>
#include <rtt/types/TypeInfo.hpp>
#include <rtt/types/TypeInfoRepository.hpp>
#include <rtt/types/Types.hpp>
#include <rtt/types/carray.hpp>

#include <cstring>
#include <string>

#include "tactile_types/types.hpp"

namespace {

// A bag that a decomposition filled: RTT leaves deleting its properties to the
// bag's user (found by the whole-suite ASan run: LeakSanitizer).
struct OwnedBag {
  RTT::PropertyBag bag;
  ~OwnedBag() { RTT::deletePropertyBag(bag); }
};

using RTT::internal::AssignableDataSource;
using RTT::internal::DataSource;
using RTT::internal::ValueDataSource;

class Env : public ::testing::Environment {
 public:
  void SetUp() override {
    __os_init(0, nullptr);
    auto loader = RTT::plugin::PluginLoader::Instance();
    ASSERT_TRUE(loader->loadTypekits(TACTILE_RTT_OWN_PACKAGE_DIR)) << "RTT typekit not found in " TACTILE_RTT_OWN_PACKAGE_DIR;
    ASSERT_TRUE(loader->loadTypekits(TACTILE_RTT_PACKAGE_DIR)) << "tactile typekit not found in " TACTILE_RTT_PACKAGE_DIR;
  }
  void TearDown() override { __os_exit(); }
};
const auto* const env = ::testing::AddGlobalTestEnvironment(new Env);

RTT::types::TypeInfo* type(const char* name) { return RTT::types::TypeInfoRepository::Instance()->type(name); }

template <typename T>
std::string rttName() {
  return RTT::internal::DataSourceTypeInfo<T>::getTypeInfo()->getTypeName();
}

// Member `name` of `ds` as an assignable data source of type M (null if absent / other type).
template <typename M>
typename AssignableDataSource<M>::shared_ptr member(RTT::base::DataSourceBase::shared_ptr ds, const std::string& name) {
  return AssignableDataSource<M>::narrow(ds->getMember(name).get());
}

TEST(RttTypekit, EveryTypeIsKnownUnderItsName) {
  for (const char* n : {"/tactile/RawTactileFrame", "/tactile/TactileFrame", "/tactile/ContactFeatures", "/tactile/Pose",
                        "/tactile/PoseCommand", "/tactile/PhaseState", "/tactile/ContactType", "/tactile/FeatureStatus",
                        "/tactile/ServoStatus", "/tactile/Wrench", "/tactile/SimTruth", "/uint16_t"})
    EXPECT_NE(type(n), nullptr) << n;
  EXPECT_EQ(rttName<tactile::Wrench>(), "/tactile/Wrench");
  EXPECT_EQ(rttName<tactile::SimTruth>(), "/tactile/SimTruth");
  EXPECT_EQ(rttName<tactile::RawTactileFrame>(), "/tactile/RawTactileFrame");
  EXPECT_EQ(rttName<tactile::TactileFrame>(), "/tactile/TactileFrame");
  EXPECT_EQ(rttName<tactile::ContactFeatures>(), "/tactile/ContactFeatures");
  EXPECT_EQ(rttName<tactile::Pose>(), "/tactile/Pose");
  EXPECT_EQ(rttName<tactile::PoseCommand>(), "/tactile/PoseCommand");
  EXPECT_EQ(rttName<tactile::PhaseState>(), "/tactile/PhaseState");
  EXPECT_EQ(rttName<tactile::ContactType>(), "/tactile/ContactType");
  EXPECT_EQ(rttName<uint16_t>(), "/uint16_t");
  EXPECT_EQ(type("/tactile/NoSuchType"), nullptr);  // the lookup can fail
}

TEST(RttTypekit, MemberNamesAreTheFieldNames) {
  const std::vector<std::string> f = type("/tactile/ContactFeatures")->getMemberNames();
  const std::vector<std::string> expected = {"time_s", "seq",     "cop_x",   "cop_y",     "coc_x", "coc_y",
                                             "dzmp_x", "dzmp_y",  "alpha_z", "force",     "d_z",   "lambda1",
                                             "lambda2", "curvature", "max_taxel", "area", "contact", "status",
                                             "alpha_defined"};
  EXPECT_EQ(f, expected);
  EXPECT_EQ(type("/tactile/Pose")->getMemberNames(), (std::vector<std::string>{"p", "q"}));
  EXPECT_EQ(type("/tactile/PhaseState")->getMemberNames(),
            (std::vector<std::string>{"time_s", "t_enter_s", "index", "name", "status"}));
  // estimated_wrench: fixed size (no std::vector on the port).
  EXPECT_EQ(type("/tactile/Wrench")->getMemberNames(), (std::vector<std::string>{"time_s", "w"}));
  EXPECT_EQ(type("/tactile/SimTruth")->getMemberNames(),
            (std::vector<std::string>{"time_s", "wrench_s", "layer_force", "housing_force", "tray_pitch", "tray_roll",
                                      "contact_point_g", "in_contact", "sensor_pose", "sim_status"}));
}

TEST(RttTypekit, PropertiesAndPortsOfEveryType) {
  RTT::TaskContext tc("holder");
  tactile::ContactFeatures cf;
  tactile::Pose pose;
  tactile::PhaseState phase;
  tc.addProperty("features", cf);
  tc.addProperty("pose", pose);
  tc.addProperty("phase", phase);
  RTT::OutputPort<tactile::RawTactileFrame> raw_out("raw");
  RTT::InputPort<tactile::TactileFrame> frame_in("frame");
  RTT::OutputPort<tactile::PoseCommand> cmd_out("cmd");
  RTT::InputPort<tactile::PoseCommand> cmd_in("cmd_in");
  tc.ports()->addPort(raw_out);
  tc.ports()->addPort(frame_in);
  tc.ports()->addPort(cmd_out);
  tc.ports()->addPort(cmd_in);
  EXPECT_EQ(tc.properties()->getProperty("features")->getType(), "/tactile/ContactFeatures");
  EXPECT_EQ(tc.properties()->getProperty("pose")->getType(), "/tactile/Pose");
  EXPECT_EQ(tc.properties()->getProperty("phase")->getType(), "/tactile/PhaseState");
  EXPECT_EQ(raw_out.getTypeInfo()->getTypeName(), "/tactile/RawTactileFrame");
  EXPECT_EQ(frame_in.getTypeInfo()->getTypeName(), "/tactile/TactileFrame");
  // A PoseCommand travels through a connection field by field.
  ASSERT_TRUE(cmd_out.connectTo(&cmd_in));
  tactile::PoseCommand c;
  c.time_s = 1.5;
  c.seq = 7;
  c.pose.p = {0.1, -0.2, 0.3};
  c.pose.q = {0.0, 0.0, 0.70710678118654757, 0.70710678118654757};
  c.status = tactile::ServoStatus::Limited;
  cmd_out.write(c);
  tactile::PoseCommand r;
  ASSERT_EQ(cmd_in.read(r), RTT::NewData);
  EXPECT_EQ(r.seq, 7u);
  EXPECT_EQ(r.pose.p, c.pose.p);
  EXPECT_EQ(r.pose.q, c.pose.q);
  EXPECT_EQ(r.status, tactile::ServoStatus::Limited);
}

TEST(RttTypekit, SetMembersThroughDataSources) {
  ValueDataSource<tactile::ContactFeatures>::shared_ptr ds = new ValueDataSource<tactile::ContactFeatures>();
  auto cop_x = member<double>(ds, "cop_x");
  ASSERT_TRUE(cop_x);
  cop_x->set(0.0042);
  EXPECT_EQ(ds->rvalue().cop_x, 0.0042);
  auto area = member<uint16_t>(ds, "area");
  ASSERT_TRUE(area);
  EXPECT_EQ(area->getTypeName(), "/uint16_t");
  area->set(17);
  EXPECT_EQ(ds->rvalue().area, 17);
  auto contact = member<tactile::ContactType>(ds, "contact");
  ASSERT_TRUE(contact);
  contact->set(tactile::ContactType::Edge);
  EXPECT_EQ(ds->rvalue().contact, tactile::ContactType::Edge);
  EXPECT_FALSE(ds->getMember("no_such_member"));

  // Array member: element 3 of TactileFrame::force, through the carray type.
  ValueDataSource<tactile::TactileFrame>::shared_ptr fr = new ValueDataSource<tactile::TactileFrame>();
  RTT::base::DataSourceBase::shared_ptr force = fr->getMember("force");
  ASSERT_TRUE(force);
  EXPECT_EQ(force->getTypeInfo()->getTypeName(), "/tactile/double[]");  // (getTypeName() of a carray is its element type)
  // (narrow() returns a raw pointer: hold the result in a shared_ptr.)
  AssignableDataSource<double>::shared_ptr elem = AssignableDataSource<double>::narrow(force->getMember("3").get());
  ASSERT_TRUE(elem);
  elem->set(1.25);
  EXPECT_EQ(fr->rvalue().force[3], 1.25);
  DataSource<int>::shared_ptr size = DataSource<int>::narrow(force->getMember("size").get());
  ASSERT_TRUE(size);
  EXPECT_EQ(size->get(), tactile::kMaxTaxels);

  // Nested struct: PoseCommand.pose.p[2].
  ValueDataSource<tactile::PoseCommand>::shared_ptr pc = new ValueDataSource<tactile::PoseCommand>();
  RTT::base::DataSourceBase::shared_ptr pose = pc->getMember("pose");
  ASSERT_TRUE(pose);
  RTT::base::DataSourceBase::shared_ptr p = pose->getMember("p");
  ASSERT_TRUE(p);
  AssignableDataSource<double>::shared_ptr pz = AssignableDataSource<double>::narrow(p->getMember("2").get());
  ASSERT_TRUE(pz);
  pz->set(0.75);
  EXPECT_EQ(pc->rvalue().pose.p[2], 0.75);
}

TEST(RttTypekit, DecompositionRoundTripsFieldValues) {
  tactile::ContactFeatures in;
  in.time_s = 2.5;
  in.seq = 99;
  in.cop_x = 0.001;
  in.cop_y = -0.002;
  in.coc_x = 0.003;
  in.coc_y = -0.004;
  in.dzmp_x = 0.005;
  in.dzmp_y = -0.006;
  in.alpha_z = 0.7;
  in.force = 3.25;
  in.d_z = 0.0018;
  in.lambda1 = 4e-5;
  in.lambda2 = 1e-6;
  in.curvature = -4.25;
  in.max_taxel = 0.9;
  in.area = 12;
  in.contact = tactile::ContactType::Edge;
  in.status = tactile::FeatureStatus::Saturated;
  in.alpha_defined = true;
  RTT::Property<tactile::ContactFeatures> prop("f", "", in);
  OwnedBag owned;
  RTT::PropertyBag& bag = owned.bag;
  ASSERT_TRUE(RTT::types::propertyDecomposition(&prop, bag));
  ASSERT_EQ(bag.size(), 19u);
  RTT::Property<bool> alpha_defined = bag.getProperty("alpha_defined");
  ASSERT_TRUE(alpha_defined.ready());
  EXPECT_TRUE(alpha_defined.value());
  auto dbl = [&](const char* n) {
    RTT::Property<double> p = bag.getProperty(n);
    EXPECT_TRUE(p.ready()) << n;
    return p.ready() ? p.value() : -1.0;
  };
  EXPECT_EQ(dbl("time_s"), 2.5);
  EXPECT_EQ(dbl("cop_x"), 0.001);
  EXPECT_EQ(dbl("coc_y"), -0.004);
  EXPECT_EQ(dbl("dzmp_y"), -0.006);
  EXPECT_EQ(dbl("alpha_z"), 0.7);
  EXPECT_EQ(dbl("force"), 3.25);
  EXPECT_EQ(dbl("lambda2"), 1e-6);
  EXPECT_EQ(dbl("curvature"), -4.25);
  RTT::Property<unsigned int> seq = bag.getProperty("seq");
  ASSERT_TRUE(seq.ready());
  EXPECT_EQ(seq.value(), 99u);
  // Enums decompose to their names.
  RTT::Property<std::string> contact = bag.getProperty("contact");
  ASSERT_TRUE(contact.ready());
  EXPECT_EQ(contact.value(), "edge");
  RTT::Property<std::string> status = bag.getProperty("status");
  ASSERT_TRUE(status.ready());
  EXPECT_EQ(status.value(), "saturated");

  // Edit the decomposed bag, compose it back into a fresh struct.
  RTT::Property<double>(bag.getProperty("cop_y")).set(0.0123);
  RTT::Property<std::string>(bag.getProperty("contact")).set("point");
  ValueDataSource<tactile::ContactFeatures>::shared_ptr out = new ValueDataSource<tactile::ContactFeatures>();
  ASSERT_TRUE(type("/tactile/ContactFeatures")->composeType(new ValueDataSource<RTT::PropertyBag>(bag), out));
  const tactile::ContactFeatures& o = out->rvalue();
  EXPECT_EQ(o.time_s, in.time_s);
  EXPECT_EQ(o.seq, in.seq);
  EXPECT_EQ(o.cop_x, in.cop_x);
  EXPECT_EQ(o.cop_y, 0.0123);
  EXPECT_EQ(o.coc_x, in.coc_x);
  EXPECT_EQ(o.coc_y, in.coc_y);
  EXPECT_EQ(o.dzmp_x, in.dzmp_x);
  EXPECT_EQ(o.dzmp_y, in.dzmp_y);
  EXPECT_EQ(o.alpha_z, in.alpha_z);
  EXPECT_EQ(o.force, in.force);
  EXPECT_EQ(o.d_z, in.d_z);
  EXPECT_EQ(o.lambda1, in.lambda1);
  EXPECT_EQ(o.lambda2, in.lambda2);
  EXPECT_EQ(o.curvature, in.curvature);
  EXPECT_EQ(o.max_taxel, in.max_taxel);
  EXPECT_EQ(o.area, in.area);
  EXPECT_EQ(o.contact, tactile::ContactType::Point);
  EXPECT_EQ(o.status, in.status);
}

// OCL's reporter decomposes a port's sample once and streams the parts every
// period: an enum's decomposed name must follow the sample, not keep the
// value it had when it was decomposed.
TEST(RttTypekit, DecomposedEnumNamesFollowTheData) {
  ValueDataSource<tactile::ContactFeatures>::shared_ptr src = new ValueDataSource<tactile::ContactFeatures>();
  src->set().contact = tactile::ContactType::None;
  src->set().status = tactile::FeatureStatus::NotConfigured;
  RTT::base::DataSourceBase::shared_ptr contact_member = src->getMember("contact");
  ASSERT_TRUE(contact_member);
  RTT::base::DataSourceBase::shared_ptr contact =
      type("/tactile/ContactType")->decomposeType(contact_member);
  auto name = DataSource<std::string>::narrow(contact.get());
  ASSERT_TRUE(name);
  EXPECT_EQ(name->get(), "none");
  src->set().contact = tactile::ContactType::Edge;
  EXPECT_EQ(name->get(), "edge");
  EXPECT_EQ(name->rvalue(), "edge");
  src->set().contact = tactile::ContactType::Point;
  EXPECT_EQ(name->rvalue(), "point");
  // The same through a whole-struct decomposition (the reporter's path).
  OwnedBag owned;
  RTT::PropertyBag& bag = owned.bag;
  ASSERT_TRUE(RTT::types::typeDecomposition(src, bag, true));
  RTT::Property<std::string> status = bag.getProperty("status");
  ASSERT_TRUE(status.ready());
  EXPECT_EQ(status.rvalue(), "not_configured");
  src->set().status = tactile::FeatureStatus::Saturated;
  EXPECT_EQ(status.rvalue(), "saturated");
}

TEST(RttTypekit, PoseAndPhaseStateRoundTrip) {
  tactile::PhaseState ph;
  ph.time_s = 4.0;
  ph.t_enter_s = 3.5;
  ph.index = 2;
  std::strncpy(ph.name.data(), "align", ph.name.size() - 1);
  ph.status = tactile::ServoStatus::Ok;
  RTT::Property<tactile::PhaseState> prop("phase", "", ph);
  OwnedBag owned;
  RTT::PropertyBag& bag = owned.bag;
  ASSERT_TRUE(RTT::types::propertyDecomposition(&prop, bag));
  RTT::Property<double>(bag.getProperty("t_enter_s")).set(3.75);
  ValueDataSource<tactile::PhaseState>::shared_ptr out = new ValueDataSource<tactile::PhaseState>();
  ASSERT_TRUE(type("/tactile/PhaseState")->composeType(new ValueDataSource<RTT::PropertyBag>(bag), out));
  EXPECT_EQ(out->rvalue().time_s, 4.0);
  EXPECT_EQ(out->rvalue().t_enter_s, 3.75);
  EXPECT_EQ(out->rvalue().index, 2);
  EXPECT_STREQ(out->rvalue().name.data(), "align");
  EXPECT_EQ(out->rvalue().status, tactile::ServoStatus::Ok);

  tactile::Pose pose;
  pose.p = {0.4, 0.5, 0.6};
  pose.q = {0.1, 0.2, 0.3, 0.927361849549570};
  RTT::Property<tactile::Pose> pp("pose", "", pose);
  OwnedBag powned;
  RTT::PropertyBag& pbag = powned.bag;
  ASSERT_TRUE(RTT::types::propertyDecomposition(&pp, pbag));
  ValueDataSource<tactile::Pose>::shared_ptr pout = new ValueDataSource<tactile::Pose>();
  ASSERT_TRUE(type("/tactile/Pose")->composeType(new ValueDataSource<RTT::PropertyBag>(pbag), pout));
  EXPECT_EQ(pout->rvalue().p, pose.p);
  EXPECT_EQ(pout->rvalue().q, pose.q);
}

TEST(RttTypekit, Uint16ConvertsToAndFromInt) {
  RTT::types::TypeInfo* u16 = type("/uint16_t");
  ASSERT_NE(u16, nullptr);
  RTT::base::DataSourceBase::shared_ptr c = u16->convert(new ValueDataSource<int>(300));
  DataSource<uint16_t>::shared_ptr cu = DataSource<uint16_t>::narrow(c.get());
  ASSERT_TRUE(cu);
  EXPECT_EQ(cu->get(), 300);
  RTT::base::DataSourceBase::shared_ptr c2 = u16->convert(new ValueDataSource<int>(-5));
  DataSource<uint16_t>::shared_ptr clamped = DataSource<uint16_t>::narrow(c2.get());
  ASSERT_TRUE(clamped);
  EXPECT_EQ(clamped->get(), 0);
  RTT::base::DataSourceBase::shared_ptr c3 = type("int")->convert(new ValueDataSource<uint16_t>(65535));
  DataSource<int>::shared_ptr back = DataSource<int>::narrow(c3.get());
  ASSERT_TRUE(back);
  EXPECT_EQ(back->get(), 65535);
}

}  // namespace

namespace {

// Evaluates `a op b` the way the script parser does (OperatorRepository).
template <typename A, typename B>
int apply(const char* op, A a, B b) {
  RTT::base::DataSourceBase::shared_ptr da = new ValueDataSource<A>(a);
  RTT::base::DataSourceBase::shared_ptr db = new ValueDataSource<B>(b);
  RTT::base::DataSourceBase::shared_ptr r = RTT::types::OperatorRepository::Instance()->applyBinary(op, da.get(), db.get());
  DataSource<bool>::shared_ptr rb = DataSource<bool>::narrow(r.get());
  if (!rb) return -1;  // no such operator
  return rb->get() ? 1 : 0;
}

TEST(RttTypekit, ScriptOperatorsOnEnumsAndUint16) {
  using tactile::ContactType;
  using tactile::FeatureStatus;
  EXPECT_EQ(apply("==", ContactType::Edge, ContactType::Edge), 1);
  EXPECT_EQ(apply("==", ContactType::Edge, ContactType::Point), 0);
  EXPECT_EQ(apply("!=", ContactType::Edge, ContactType::Point), 1);
  EXPECT_EQ(apply("==", ContactType::Edge, 2), 1);  // int right-hand side
  EXPECT_EQ(apply("==", ContactType::Edge, 1), 0);
  EXPECT_EQ(apply("==", FeatureStatus::Saturated, std::string("saturated")), 1);
  EXPECT_EQ(apply("==", FeatureStatus::Saturated, std::string("ok")), 0);
  EXPECT_EQ(apply("!=", tactile::ServoStatus::Done, std::string("done")), 0);
  // The watchdog statuses have their names in the typekit's table too.
  EXPECT_EQ(apply("==", tactile::ServoStatus::PhaseTimeout, std::string("phase_timeout")), 1);
  EXPECT_EQ(apply("==", tactile::ServoStatus::ArmStalled, std::string("arm_stalled")), 1);
  EXPECT_EQ(apply("==", tactile::ServoStatus::ForceMismatch, std::string("force_mismatch")), 1);
  EXPECT_EQ(apply("==", tactile::ServoStatus::SurfaceTooCurved, std::string("surface_too_curved")), 1);
  EXPECT_EQ(apply("==", tactile::ServoStatus::ForceMismatch, 15), 1);
  EXPECT_EQ(apply("==", uint16_t{3}, 3), 1);
  EXPECT_EQ(apply(">", uint16_t{3}, 5), 0);
  EXPECT_EQ(apply(">", uint16_t{3}, -1), 1);  // compared as int: no clamping of -1
  EXPECT_EQ(apply("<=", uint16_t{65535}, 65535), 1);
  EXPECT_EQ(apply("==", uint16_t{7}, uint16_t{7}), 1);  // uint16_t right-hand side converts
  EXPECT_EQ(apply("<", 2, uint16_t{7}), 1);              // int on the left: uint16_t converts
}

}  // namespace
