// boost::serialization description of the shared plain types (types.hpp).
//
// The RTT typekit (typekit.cpp) builds its StructTypeInfo<T> from these
// functions: RTT's type_discovery archive walks them to give every field a
// name, so ports, properties and ops scripts can read and set members
// ("features.cop_x", "frame.force[3]"). The field names are the C++ member
// names. Fixed-size std::array members are exposed as C arrays (RTT carray),
// enums as their own RTT types (integer or name, see typekit.cpp).
//
// Plain header: no RTT include, usable by any boost archive.
#pragma once

#include <boost/serialization/array_wrapper.hpp>
#include <boost/serialization/nvp.hpp>
#include <boost/serialization/serialization.hpp>

#include <array>
#include <cstddef>

#include "tactile_types/types.hpp"

namespace boost {
namespace serialization {

namespace tactile_detail {
// make_nvp() needs an lvalue; the wrapper only holds a pointer and a count.
// It must be const: RTT's type_discovery maps `const array_wrapper<T>&` to a
// carray<T> member.
template <class Archive, typename T, std::size_t N>
void array(Archive& a, const char* name, std::array<T, N>& v) {
  const auto w = boost::serialization::make_array(v.data(), N);
  a& boost::serialization::make_nvp(name, w);
}
}  // namespace tactile_detail

template <class Archive>
void serialize(Archive& a, tactile::RawTactileFrame& f, const unsigned int) {
  a& make_nvp("time_s", f.time_s);
  a& make_nvp("seq", f.seq);
  a& make_nvp("device_time_ms", f.device_time_ms);
  a& make_nvp("rows", f.rows);
  a& make_nvp("cols", f.cols);
  tactile_detail::array(a, "counts", f.counts);
}

template <class Archive>
void serialize(Archive& a, tactile::TactileFrame& f, const unsigned int) {
  a& make_nvp("time_s", f.time_s);
  a& make_nvp("seq", f.seq);
  a& make_nvp("rows", f.rows);
  a& make_nvp("cols", f.cols);
  a& make_nvp("saturated_count", f.saturated_count);
  tactile_detail::array(a, "force", f.force);
}

template <class Archive>
void serialize(Archive& a, tactile::ContactFeatures& f, const unsigned int) {
  a& make_nvp("time_s", f.time_s);
  a& make_nvp("seq", f.seq);
  a& make_nvp("cop_x", f.cop_x);
  a& make_nvp("cop_y", f.cop_y);
  a& make_nvp("coc_x", f.coc_x);
  a& make_nvp("coc_y", f.coc_y);
  a& make_nvp("dzmp_x", f.dzmp_x);
  a& make_nvp("dzmp_y", f.dzmp_y);
  a& make_nvp("alpha_z", f.alpha_z);
  a& make_nvp("force", f.force);
  a& make_nvp("d_z", f.d_z);
  a& make_nvp("lambda1", f.lambda1);
  a& make_nvp("lambda2", f.lambda2);
  a& make_nvp("curvature", f.curvature);
  a& make_nvp("max_taxel", f.max_taxel);
  a& make_nvp("area", f.area);
  a& make_nvp("contact", f.contact);
  a& make_nvp("status", f.status);
  a& make_nvp("alpha_defined", f.alpha_defined);
}

template <class Archive>
void serialize(Archive& a, tactile::Pose& p, const unsigned int) {
  tactile_detail::array(a, "p", p.p);
  tactile_detail::array(a, "q", p.q);
}

template <class Archive>
void serialize(Archive& a, tactile::PoseCommand& c, const unsigned int) {
  a& make_nvp("time_s", c.time_s);
  a& make_nvp("seq", c.seq);
  a& make_nvp("pose", c.pose);
  a& make_nvp("status", c.status);
}

template <class Archive>
void serialize(Archive& a, tactile::PhaseState& s, const unsigned int) {
  a& make_nvp("time_s", s.time_s);
  a& make_nvp("t_enter_s", s.t_enter_s);
  a& make_nvp("index", s.index);
  tactile_detail::array(a, "name", s.name);
  a& make_nvp("status", s.status);
}

template <class Archive>
void serialize(Archive& a, tactile::Wrench& w, const unsigned int) {
  a& make_nvp("time_s", w.time_s);
  tactile_detail::array(a, "w", w.w);
}

template <class Archive>
void serialize(Archive& a, tactile::RobotState& r, const unsigned int) {
  a& make_nvp("time_s", r.time_s);
  a& make_nvp("mode", r.mode);
  a& make_nvp("quality", r.quality);
  a& make_nvp("power_on", r.power_on);
  a& make_nvp("cartesian_impedance", r.cartesian_impedance);
  a& make_nvp("config_ok", r.config_ok);
  a& make_nvp("dry_run", r.dry_run);
  a& make_nvp("commandable", r.commandable);
  a& make_nvp("link_status", r.link_status);
  tactile_detail::array(a, "q", r.q);
  a& make_nvp("setpoint", r.setpoint);
}

template <class Archive>
void serialize(Archive& a, tactile::SimTruth& t, const unsigned int) {
  a& make_nvp("time_s", t.time_s);
  tactile_detail::array(a, "wrench_s", t.wrench_s);
  a& make_nvp("layer_force", t.layer_force);
  a& make_nvp("housing_force", t.housing_force);
  a& make_nvp("tray_pitch", t.tray_pitch);
  a& make_nvp("tray_roll", t.tray_roll);
  tactile_detail::array(a, "contact_point_g", t.contact_point_g);
  a& make_nvp("in_contact", t.in_contact);
  a& make_nvp("sensor_pose", t.sensor_pose);
  a& make_nvp("sim_status", t.sim_status);
}

}  // namespace serialization
}  // namespace boost
