// RTT typekit plugin for the shared plain types (see typekit.hpp for the names).
#include "tactile_types_rtt/typekit.hpp"

#include <rtt/types/CArrayTypeInfo.hpp>
#include <rtt/types/OperatorTypes.hpp>
#include <rtt/types/Operators.hpp>
#include <rtt/internal/DataSources.hpp>
#include <rtt/types/StructTypeInfo.hpp>
#include <rtt/types/TemplateConstructor.hpp>
#include <rtt/types/TemplateTypeInfo.hpp>
#include <rtt/types/TypeInfoRepository.hpp>
#include <rtt/types/Types.hpp>
#include <rtt/types/carray.hpp>

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <utility>

#include "tactile_types/types.hpp"
#include "tactile_types_rtt/serialization.hpp"

namespace tactile {
namespace rtt_types {
namespace {

/// The name of an enum value, read through from its source: every read
/// (get/value/rvalue) re-reads the source and renames it when the value
/// changed, so a decomposition made once (OCL's reporter decomposes a port's
/// sample at configure() and streams the parts every period) follows the
/// data. set() overrides the name until the source changes (a decomposed
/// property bag edited before it is composed back).
template <typename E>
class EnumNameDataSource : public RTT::internal::AssignableDataSource<std::string> {
 public:
  explicit EnumNameDataSource(typename RTT::internal::DataSource<E>::shared_ptr src) : src_(std::move(src)) {
    refresh();
  }
  std::string get() const override { return refresh(); }
  std::string value() const override { return refresh(); }
  const std::string& rvalue() const override { return refresh(); }
  void set(typename RTT::internal::AssignableDataSource<std::string>::param_t t) override { name_ = t; }
  std::string& set() override { return name_; }
  EnumNameDataSource* clone() const override { return new EnumNameDataSource(src_); }
  EnumNameDataSource* copy(std::map<const RTT::base::DataSourceBase*, RTT::base::DataSourceBase*>& done) const override {
    const auto it = done.find(this);
    if (it != done.end()) return static_cast<EnumNameDataSource*>(it->second);
    auto* c = new EnumNameDataSource(src_->copy(done));
    done[this] = c;
    return c;
  }

 private:
  const std::string& refresh() const {
    src_->evaluate();
    const E e = src_->rvalue();
    if (!seen_ || e != last_) {
      seen_ = true;
      last_ = e;
      name_ = tactile::toString(e);
    }
    return name_;
  }
  typename RTT::internal::DataSource<E>::shared_ptr src_;
  mutable bool seen_ = false;
  mutable E last_{};
  mutable std::string name_;
};

/// Enums (enum class, uint8_t based): automatic conversion to and from int,
/// and decomposition to the value's name (property files, reporting, the task
/// browser); composition accepts the name or an int. RTT's EnumTypeInfo
/// assumes implicitly convertible (unscoped) enums, hence this version.
template <typename E, int kCount>
class NamedEnumTypeInfo : public RTT::types::TemplateTypeInfo<E, false> {
 public:
  NamedEnumTypeInfo(const std::string& name, const E (&values)[kCount]) : RTT::types::TemplateTypeInfo<E, false>(name) {
    for (int i = 0; i < kCount; ++i) values_[i] = values[i];
  }

  bool installTypeInfoObject(RTT::types::TypeInfo* ti) override {
    RTT::types::TemplateTypeInfo<E, false>::installTypeInfoObject(ti);
    if (RTT::types::TypeInfo* int_ti = RTT::types::Types()->type("int"))
      int_ti->addConstructor(RTT::types::newConstructor(&toInt, true));
    ti->addConstructor(RTT::types::newConstructor(&fromInt, true));
    return false;  // memory-managed by the repository
  }

  RTT::base::DataSourceBase::shared_ptr decomposeType(RTT::base::DataSourceBase::shared_ptr source) const override {
    typename RTT::internal::DataSource<E>::shared_ptr ds = RTT::internal::DataSource<E>::narrow(source.get());
    if (!ds) return RTT::base::DataSourceBase::shared_ptr();
    return new EnumNameDataSource<E>(ds);  // live: follows the source (reporting)
  }

  bool composeType(RTT::base::DataSourceBase::shared_ptr source,
                   RTT::base::DataSourceBase::shared_ptr result) const override {
    typename RTT::internal::AssignableDataSource<E>::shared_ptr out =
        RTT::internal::AssignableDataSource<E>::narrow(result.get());
    if (!out) return false;
    if (result->update(source.get())) return true;
    if (auto i = RTT::internal::DataSource<int>::narrow(source.get())) {
      for (const E v : values_)
        if (static_cast<int>(v) == i->get()) {
          out->set(v);
          return true;
        }
      return false;  // not a value of this enum
    }
    if (auto s = RTT::internal::DataSource<std::string>::narrow(source.get())) {
      for (const E v : values_)
        if (s->get() == toString(v)) {
          out->set(v);
          return true;
        }
    }
    return false;
  }

 private:
  static int toInt(E e) { return static_cast<int>(e); }
  static E fromInt(int i) { return static_cast<E>(i); }
  E values_[kCount];
};

/// uint16_t: frame sizes, taxel counts, phase index. Streams like an unsigned
/// number and converts automatically to and from int (clamped to [0, 65535])
/// so scripts can compare and assign it with integer literals.
class Uint16TypeInfo : public RTT::types::TemplateTypeInfo<uint16_t, true> {
 public:
  Uint16TypeInfo() : RTT::types::TemplateTypeInfo<uint16_t, true>(kUint16) {}
  bool installTypeInfoObject(RTT::types::TypeInfo* ti) override {
    RTT::types::TemplateTypeInfo<uint16_t, true>::installTypeInfoObject(ti);
    if (RTT::types::TypeInfo* int_ti = RTT::types::Types()->type("int"))
      int_ti->addConstructor(RTT::types::newConstructor(&toInt, true));
    ti->addConstructor(RTT::types::newConstructor(&fromInt, true));
    return false;  // memory-managed by the repository
  }

 private:
  static int toInt(uint16_t v) { return static_cast<int>(v); }
  static uint16_t fromInt(int v) {
    if (v < 0) return 0;
    if (v > std::numeric_limits<uint16_t>::max()) return std::numeric_limits<uint16_t>::max();
    return static_cast<uint16_t>(v);
  }
};

// Binary operators for scripts. RTT matches the first operand's type exactly
// and converts the second one (automatic constructors), so each type gets its
// own operators; the right-hand side may be an int (or a name, for enums).
template <typename A, typename B, typename Cmp>
struct Compare {
  typedef A first_argument_type;
  typedef B second_argument_type;
  typedef bool result_type;
  bool operator()(const A& a, const B& b) const { return Cmp()(a, b); }
};

template <typename E>
struct NameEquals {
  typedef E first_argument_type;
  typedef std::string second_argument_type;
  typedef bool result_type;
  bool equal;
  bool operator()(const E& a, const std::string& b) const { return (b == toString(a)) == equal; }
};

struct IntCmp {
  int op;  // 0 ==, 1 !=, 2 <, 3 >, 4 <=, 5 >=
  bool operator()(int a, int b) const {
    switch (op) {
      case 0: return a == b;
      case 1: return a != b;
      case 2: return a < b;
      case 3: return a > b;
      case 4: return a <= b;
      default: return a >= b;
    }
  }
};
struct U16IntCmp {
  typedef uint16_t first_argument_type;
  typedef int second_argument_type;
  typedef bool result_type;
  int op;
  bool operator()(const uint16_t& a, const int& b) const { return IntCmp{op}(static_cast<int>(a), b); }
};

template <typename E>
void addEnumOperators(RTT::types::OperatorRepository::shared_ptr ops) {
  ops->add(RTT::types::newBinaryOperator("==", Compare<E, E, std::equal_to<E>>()));
  ops->add(RTT::types::newBinaryOperator("!=", Compare<E, E, std::not_equal_to<E>>()));
  ops->add(RTT::types::newBinaryOperator("==", NameEquals<E>{true}));
  ops->add(RTT::types::newBinaryOperator("!=", NameEquals<E>{false}));
}

}  // namespace

bool TactileTypekit::loadTypes() {
  using RTT::types::CArrayTypeInfo;
  using RTT::types::StructTypeInfo;
  using RTT::types::carray;
  RTT::types::TypeInfoRepository::shared_ptr repo = RTT::types::TypeInfoRepository::Instance();

  // Member types first: a struct's members are looked up by type when it is decomposed.
  repo->addType(new Uint16TypeInfo());
  repo->addType(new CArrayTypeInfo<carray<double>>("/tactile/double[]"));
  repo->addType(new CArrayTypeInfo<carray<uint16_t>>("/tactile/uint16_t[]"));
  repo->addType(new CArrayTypeInfo<carray<char>>("/tactile/char[]"));

  static const ContactType contact_types[] = {ContactType::None, ContactType::Point, ContactType::Edge,
                                              ContactType::Multiple};
  static const FeatureStatus feature_status[] = {FeatureStatus::Ok,           FeatureStatus::NoContact,
                                                 FeatureStatus::Saturated,    FeatureStatus::TareRejected,
                                                 FeatureStatus::InvalidInput, FeatureStatus::BadDimensions,
                                                 FeatureStatus::NotConfigured, FeatureStatus::OutOfRange};
  static const ServoStatus servo_status[] = {ServoStatus::Ok,           ServoStatus::FreeMotion, ServoStatus::Holding,
                                             ServoStatus::ContactLost,  ServoStatus::Limited,    ServoStatus::Done,
                                             ServoStatus::WaitingForPose, ServoStatus::Starting,
                                             ServoStatus::WaitingForRobot,
                                             ServoStatus::ForceCeiling, ServoStatus::InvalidInput,
                                             ServoStatus::NotConfigured, ServoStatus::PhaseTimeout,
                                             ServoStatus::ArmStalled,   ServoStatus::ForceMismatch,
                                             ServoStatus::SurfaceTooCurved, ServoStatus::PhantomContact,
                                             ServoStatus::UnseenLoad,   ServoStatus::CorrectionSaturated,
                                             ServoStatus::CorrectionDrift};
  repo->addType(new NamedEnumTypeInfo<ContactType, 4>(kContactType, contact_types));
  repo->addType(new NamedEnumTypeInfo<FeatureStatus, 8>(kFeatureStatus, feature_status));
  repo->addType(new NamedEnumTypeInfo<ServoStatus, 20>(kServoStatus, servo_status));
  static const RobotMode robot_modes[] = {RobotMode::Off, RobotMode::Monitor, RobotMode::Command};
  repo->addType(new NamedEnumTypeInfo<RobotMode, 3>(kRobotMode, robot_modes));

  repo->addType(new StructTypeInfo<RawTactileFrame>(kRawTactileFrame));
  repo->addType(new StructTypeInfo<TactileFrame>(kTactileFrame));
  repo->addType(new StructTypeInfo<ContactFeatures>(kContactFeatures));
  repo->addType(new StructTypeInfo<Pose>(kPose));
  repo->addType(new StructTypeInfo<PoseCommand>(kPoseCommand));
  repo->addType(new StructTypeInfo<PhaseState>(kPhaseState));
  repo->addType(new StructTypeInfo<Wrench>(kWrench));
  repo->addType(new StructTypeInfo<SimTruth>(kSimTruth));
  repo->addType(new StructTypeInfo<RobotState>(kRobotState));
  return true;
}

bool TactileTypekit::loadOperators() {
  RTT::types::OperatorRepository::shared_ptr ops = RTT::types::OperatorRepository::Instance();
  // enum == enum (an int right-hand side converts), enum == "name"
  addEnumOperators<ContactType>(ops);
  addEnumOperators<FeatureStatus>(ops);
  addEnumOperators<ServoStatus>(ops);
  addEnumOperators<RobotMode>(ops);
  // uint16_t compared with int (a uint16_t right-hand side converts to int)
  const char* names[6] = {"==", "!=", "<", ">", "<=", ">="};
  for (int i = 0; i < 6; ++i) ops->add(RTT::types::newBinaryOperator(names[i], U16IntCmp{i}));
  return true;
}
bool TactileTypekit::loadConstructors() { return true; }

}  // namespace rtt_types
}  // namespace tactile

ORO_TYPEKIT_PLUGIN(tactile::rtt_types::TactileTypekit)
