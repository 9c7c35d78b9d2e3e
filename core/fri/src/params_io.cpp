#include "tactile_fri/params_io.hpp"

#include <string>
#include <vector>

namespace tactile {
namespace fri {

using config::checkKeys;
using config::read;
using config::Where;

namespace {
ConfigResult readSix(const YAML::Node& node, const char* key, std::array<double, 6>& out, const Where& where) {
  if (!node[key]) return ConfigResult::success();
  std::vector<double> v;
  ConfigResult r = read(node, key, v, where);
  if (!r) return r;
  if (v.size() != 6) return rangeError(where.child(key).str() + " (length)", v.size(), "must have 6 entries");
  for (std::size_t i = 0; i < 6; ++i) out[i] = v[i];
  return ConfigResult::success();
}
}  // namespace

ConfigResult loadBridgeParams(const YAML::Node& node, const Where& where, BridgeParams& bp, UdpParams& up) {
  if (node) {
    ConfigResult r = checkKeys(node, where,
                               {"max_lin_speed", "max_rot_speed", "cycle_time_s", "max_desired_age_s",
                                "engage_max_trans", "engage_max_rot", "resync_after", "rewind_on_refl", "command_impedance", "cart_stiffness",
                                "cart_damping", "cart_offset", "wrench_frame", "setpoint_max_dev", "setpoint_max_dev_rot", "stop_krc_on_servo_fault", "udp"});
    if (!r) return r;
    for (auto rr : {read(node, "max_lin_speed", bp.max_lin_speed, where),
                    read(node, "max_rot_speed", bp.max_rot_speed, where),
                    read(node, "cycle_time_s", bp.cycle_time_s, where),
                    read(node, "max_desired_age_s", bp.max_desired_age_s, where),
                    read(node, "engage_max_trans", bp.engage_max_trans, where),
                    read(node, "engage_max_rot", bp.engage_max_rot, where),
                    read(node, "resync_after", bp.resync_after, where),
                    read(node, "rewind_on_refl", bp.rewind_on_refl, where),
                    read(node, "command_impedance", bp.command_impedance, where),
                    readSix(node, "cart_stiffness", bp.cart_stiffness, where),
                    readSix(node, "cart_damping", bp.cart_damping, where),
                    read(node, "setpoint_max_dev", bp.setpoint_max_dev, where),
                    read(node, "setpoint_max_dev_rot", bp.setpoint_max_dev_rot, where),
                    read(node, "stop_krc_on_servo_fault", bp.stop_krc_on_servo_fault, where)})
      if (!rr) return rr;
    if (node["cart_offset"]) {
      std::string form;
      if (!(r = read(node, "cart_offset", form, where))) return r;
      if (!parseCartOffset(form.c_str(), bp.cart_offset))
        return ConfigResult::failure(where.child("cart_offset").str() + ": '" + form +
                                     "' is not none, composed or elementwise (fri_check tells the KRC's form)");
    }
    if (node["wrench_frame"]) {
      std::string frame;
      if (!(r = read(node, "wrench_frame", frame, where))) return r;
      if (!parseWrenchFrame(frame.c_str(), bp.wrench_frame))
        return ConfigResult::failure(where.child("wrench_frame").str() + ": '" + frame +
                                     "' is not base or tool (the KRC's $STIFFNESS.FRAMETYPE #BASE or #TOOL; "
                                     "fri_check --wrench-check tells which one the KRC uses)");
    }
    if (const YAML::Node u = node["udp"]) {
      const Where uw = where.child("udp");
      if (!(r = checkKeys(u, uw, {"bind_address", "port", "krc_port"}))) return r;
      if (!(r = read(u, "bind_address", up.bind_address, uw))) return r;
      int port = up.port;
      if (!(r = read(u, "port", port, uw))) return r;
      if (port < 0 || port > 65535) return rangeError(uw.child("port").str(), port, "must be in [0, 65535]");
      up.port = static_cast<uint16_t>(port);
      if (!(r = read(u, "krc_port", bp.krc_port, uw))) return r;
    }
  }
  FriBridge scratch;
  const ConfigResult v = scratch.configure(bp);
  if (!v) return ConfigResult::failure((where.file.empty() ? std::string() : where.file + ": ") + v.message());
  return v;
}

ConfigResult loadBridgeParamsFile(const std::string& file, BridgeParams& bp, UdpParams& up) {
  YAML::Node root;
  ConfigResult r = config::loadFile(file, root);
  if (!r) return r;
  return loadBridgeParams(root["fri"], Where{file, "fri"}, bp, up);
}

}  // namespace fri
}  // namespace tactile
