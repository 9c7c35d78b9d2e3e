#include "tactile_wts/params_io.hpp"

namespace tactile {
namespace wts {

using config::checkKeys;
using config::read;

ConfigResult loadWtsParams(const YAML::Node& node, const config::Where& where, WtsParams& p) {
  if (!node) return ConfigResult::success();
  ConfigResult r = checkKeys(node, where,
                             {"device", "rows", "cols", "transpose", "flip_rows", "flip_cols", "periodic_ms", "rle",
                              "command_timeout_ms", "reconnect_period_s", "restart_after_s", "check_matrix_info"});
  if (!r) return r;
  for (const ConfigResult& rr :
       {read(node, "device", p.device, where), read(node, "rows", p.cells.rows, where),
        read(node, "cols", p.cells.cols, where), read(node, "transpose", p.cells.transpose, where),
        read(node, "flip_rows", p.cells.flip_rows, where), read(node, "flip_cols", p.cells.flip_cols, where),
        read(node, "periodic_ms", p.periodic_ms, where), read(node, "rle", p.rle, where),
        read(node, "command_timeout_ms", p.command_timeout_ms, where),
        read(node, "reconnect_period_s", p.reconnect_period_s, where),
        read(node, "restart_after_s", p.restart_after_s, where),
        read(node, "check_matrix_info", p.check_matrix_info, where)})
    if (!rr) return rr;
  WtsDriver scratch;  // validates every range; the messages name "wts.<key>"
  return config::locate(scratch.configure(p), where);
}

}  // namespace wts
}  // namespace tactile
