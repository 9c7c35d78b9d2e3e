#include "tactile_fri/sim_krc.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>

namespace tactile {
namespace fri {

namespace {
double nowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
constexpr double kStandardGravity = 9.80665;  // m/s^2
constexpr std::array<double, kNumJoints> kHomeJoints{{0.0, 0.5, 0.0, -1.2, 0.0, 0.6, 0.0}};
}  // namespace

// ---- FirstOrderPlant ----------------------------------------------------------

void FirstOrderPlant::reset(const KDL::Frame& initial_pose) {
  state_ = PlantState{};
  state_.q = kHomeJoints;
  state_.pose = initial_pose;
  fillWrench();
}

void FirstOrderPlant::fillWrench() {
  state_.wrench = wrench_;
  if (tool_axes_) {
    for (int part = 0; part < 2; ++part) {  // force, then moment
      const auto k = static_cast<std::size_t>(3 * part);
      const KDL::Vector v = state_.pose.M * KDL::Vector(wrench_[k], wrench_[k + 1], wrench_[k + 2]);
      for (int i = 0; i < 3; ++i) state_.wrench[k + static_cast<std::size_t>(i)] = v(i);
    }
  }
  // the load the KRC does not compensate: its weight at its centre of mass
  const KDL::Vector g(0.0, 0.0, -kStandardGravity);
  const KDL::Vector f = g * load_dm_;
  const KDL::Vector m = (state_.pose.M * load_s_) * g;
  for (int i = 0; i < 3; ++i) {
    state_.wrench[static_cast<std::size_t>(i)] += f(i);
    state_.wrench[static_cast<std::size_t>(i + 3)] += m(i);
  }
}

void FirstOrderPlant::step(const KDL::Frame& commanded, double dt, PlantState& out) {
  const double a = tau_ > 0.0 ? std::min(1.0, dt / tau_) : 1.0;
  state_.pose.p = state_.pose.p + (commanded.p - state_.pose.p) * a;
  KDL::Vector axis;
  const double angle = rotationAngle(state_.pose.M.Inverse() * commanded.M, axis);
  if (angle > 1e-12) state_.pose.M = state_.pose.M * KDL::Rotation::Rot2(axis, a * angle);
  fillWrench();
  out = state_;
}

// ---- SimKrc -------------------------------------------------------------------

ConfigResult SimKrc::configure(const SimKrcParams& p, Plant& plant) {
  if (!(std::isfinite(p.period_s) && p.period_s > 0.0 && p.period_s <= 0.1))
    return rangeError("sim_krc.period_s", p.period_s, "must be in (0, 0.1] (s)");
  if (!(std::isfinite(p.reply_timeout_s) && p.reply_timeout_s >= 0.0 && p.reply_timeout_s <= 1.0))
    return rangeError("sim_krc.reply_timeout_s", p.reply_timeout_s, "must be in [0, 1] (s)");
  if (!(std::isfinite(p.msr_sample_time_s) && p.msr_sample_time_s >= 0.0 && p.msr_sample_time_s <= 0.1))
    return rangeError("sim_krc.msr_sample_time_s", p.msr_sample_time_s, "must be in [0, 0.1] (s; 0 = period_s)");
  if (!(std::isfinite(p.cmd_sample_time_s) && p.cmd_sample_time_s >= 0.0 && p.cmd_sample_time_s <= 0.1))
    return rangeError("sim_krc.cmd_sample_time_s", p.cmd_sample_time_s, "must be in [0, 0.1] (s; 0 = period_s)");
  const double probs[] = {p.faults.loss,  p.faults.duplicate, p.faults.reorder, p.faults.late,
                          p.faults.wrong_size, p.faults.wrong_id, p.faults.cmd_loss};
  const char* names[] = {"loss", "duplicate", "reorder", "late", "wrong_size", "wrong_id", "cmd_loss"};
  for (int i = 0; i < 7; ++i) {
    if (!(probs[i] >= 0.0 && probs[i] <= 1.0))
      return rangeError(std::string("sim_krc.faults.") + names[i], probs[i], "must be a probability in [0, 1]");
  }
  for (std::size_t i = 1; i < p.schedule.size(); ++i) {
    if (p.schedule[i].cycle < p.schedule[i - 1].cycle)
      return rangeError("sim_krc.schedule[" + std::to_string(i) + "].cycle", p.schedule[i].cycle,
                        "must be >= the previous event's cycle (sorted)");
  }
  params_ = p;
  plant_ = &plant;
  KrcModelParams mp;
  mp.period_s = p.period_s;
  mp.control = p.control;
  mp.cart_offset = p.cart_offset;
  mp.quality_rule = p.quality_rule;
  mp.limits = p.limits;
  mp.wrench_frame = p.wrench_frame;
  ConfigResult r = model_.configure(mp);
  if (!r) return r;
  UdpParams up;
  up.bind_address = "127.0.0.1";
  up.port = p.local_port;  // 0: ephemeral
  r = socket_.open(up);
  if (!r) return r;
  remote_ = loopbackAddress(p.remote_port);  // loopback only, by construction
  rng_.seed(p.faults.seed);
  stats_ = SimKrcStats{};
  next_event_ = 0;
  held_size_ = 0;
  answer_rate_ = 1.0;
  plant_->reset(p.initial_pose);
  plant_->step(p.initial_pose, 0.0, plant_state_);
  model_.reset(plant_->holdPose(plant_state_));  // the robot's own set point until a command is taken
  model_.setState(p.initial.state, p.initial.quality, p.initial.power);
  open_ = p.initial.open;
  msr_ = MsrPacket{};
  t0_ = nowSeconds();
  return ConfigResult::success();
}

void SimKrc::buildMeasurement() {
  model_.buildMeasurement(plant_state_, static_cast<double>(stats_.cycles) * params_.period_s, msr_);
  // The transport's statistics (this peer's, not the model's).
  MsrPacket& m = msr_;
  if (params_.msr_sample_time_s > 0.0) m.intf.desired_msr_sample_time = static_cast<float>(params_.msr_sample_time_s);
  if (params_.cmd_sample_time_s > 0.0) m.intf.desired_cmd_sample_time = static_cast<float>(params_.cmd_sample_time_s);
  m.intf.stat.answer_rate = static_cast<float>(answer_rate_);
  m.intf.stat.miss_rate = static_cast<float>(1.0 - answer_rate_);
  m.intf.stat.miss_counter = static_cast<uint32_t>(stats_.missed);
  m.intf.stat.latency = stats_.replies ? static_cast<float>(stats_.sum_latency_s / double(stats_.replies)) : 0.0f;
}

void SimKrc::syncStats() {
  static_cast<KrcModelStats&>(stats_) = model_.stats();  // the model's counters; the peer's own stay
}

void SimKrc::sendMeasurement(const uint8_t* buf, std::size_t n) {
  socket_.sendTo(remote_, buf, n);
  ++stats_.sent;
}

void SimKrc::handleReply(const uint8_t* buf, std::size_t n, double t_sent, double now) {
  if (params_.faults.cmd_loss > 0.0 && uni_(rng_) < params_.faults.cmd_loss) {
    ++stats_.inj_cmd_lost;
    return;
  }
  const ReplyResult r = model_.handleReply(buf, n);
  syncStats();
  if (r == ReplyResult::Stale && latency_log_ != nullptr) {
    // A reply to an earlier measurement: its true latency, if that cycle has none yet.
    const uint16_t refl = model_.lastCommand().head.refl_seq;
    for (const SentRecord& rec : sent_ring_) {
      if (!rec.valid || rec.seq != refl || rec.log_index >= latency_log_->size()) continue;
      LatencySample& sample = (*latency_log_)[rec.log_index];
      if (std::isnan(sample.latency_s)) sample = LatencySample{now - rec.t_sent, false};
      break;
    }
  }
  if (r != ReplyResult::Matched) return;
  const double lat = now - t_sent;
  if (std::isnan(cycle_latency_s_)) cycle_latency_s_ = lat;
  stats_.sum_latency_s += lat;
  stats_.max_latency_s = std::max(stats_.max_latency_s, lat);
}

// Step 3 of runCycle: the measurement (n bytes in out_) sent, or not, with the
// configured faults; a packet held back in an earlier cycle after it.
bool SimKrc::sendWithFaults(std::size_t n, bool& late) {
  bool expect_reply = true;
  bool held_now = false;
  const FaultParams& f = params_.faults;
  if (f.burst_length > 0 && stats_.cycles >= f.burst_start && stats_.cycles - f.burst_start < f.burst_length) {
    ++stats_.inj_lost;  // the burst: not sent, no draw from the generator
    expect_reply = false;
  } else if (f.loss > 0.0 && uni_(rng_) < f.loss) {
    ++stats_.inj_lost;
    expect_reply = false;
  } else if (f.wrong_size > 0.0 && uni_(rng_) < f.wrong_size) {
    ++stats_.inj_wrong_size;
    const std::size_t bad = static_cast<std::size_t>(uni_(rng_) * 1200.0);
    sendMeasurement(out_.data(), bad == kMsrPacketSize ? bad + 1 : bad);
    expect_reply = false;
  } else if (f.wrong_id > 0.0 && uni_(rng_) < f.wrong_id) {
    ++stats_.inj_wrong_id;
    const uint16_t bad_id = kDatagramIdCmd;
    std::memcpy(out_.data() + offsetof(Header, datagram_id), &bad_id, 2);
    sendMeasurement(out_.data(), n);
    expect_reply = false;
  } else if (f.reorder > 0.0 && held_size_ == 0 && uni_(rng_) < f.reorder) {
    ++stats_.inj_reorder;
    std::memcpy(held_.data(), out_.data(), n);
    held_size_ = n;
    held_now = true;
    expect_reply = false;
  } else if (f.late > 0.0 && uni_(rng_) < f.late) {
    ++stats_.inj_late;
    late = true;
    expect_reply = false;
  } else {
    sendMeasurement(out_.data(), n);
    if (f.duplicate > 0.0 && uni_(rng_) < f.duplicate) {
      ++stats_.inj_duplicate;
      sendMeasurement(out_.data(), n);
    }
  }
  if (held_size_ != 0 && !held_now) {
    // a packet held back in an earlier cycle goes out after this cycle's one
    sendMeasurement(held_.data(), held_size_);
    held_size_ = 0;
  }
  return expect_reply;
}

// Step 4 of runCycle: the wait for the reply to the measurement sent at
// t_sent, up to the reply timeout or (real time) the next tick of the period.
bool SimKrc::awaitReply(double t_sent, bool expect_reply) {
  const double T = params_.period_s;
  double deadline = expect_reply ? t_sent + params_.reply_timeout_s : t_sent;
  if (params_.real_time) {
    // Next tick of the period grid, but at least half a period for the reply.
    // After an overrun of more than two periods (host hiccup) the grid is
    // re-anchored instead of sending a burst of catch-up packets.
    deadline = t0_ + double(stats_.cycles + 1) * T;
    if (t_sent - deadline > 2.0 * T) {
      ++stats_.overruns;
      t0_ = t_sent - double(stats_.cycles) * T;
      deadline = t_sent + T;
    }
    deadline = std::max(deadline, t_sent + 0.5 * T);
  }
  bool matched = false;
  for (;;) {
    const double now = nowSeconds();
    const double remaining = deadline - now;
    std::size_t rn = 0;
    const UdpStatus s = socket_.receive(in_.data(), in_.size(), rn, remaining > 0 ? int64_t(remaining * 1e6) : 0);
    if (s == UdpStatus::Ok || s == UdpStatus::Truncated) {
      const uint64_t before = stats_.replies;
      handleReply(in_.data(), s == UdpStatus::Truncated ? in_.size() + 1 : rn, t_sent, nowSeconds());
      if (stats_.replies != before) {
        matched = true;
        if (!params_.real_time) break;
      }
      continue;
    }
    if (nowSeconds() >= deadline) break;
  }
  return matched;
}

void SimKrc::runCycle() {
  if (plant_ == nullptr) return;
  const double T = params_.period_s;
  if (stats_.cycles == 0) t0_ = nowSeconds();
  cycle_latency_s_ = std::nan("");
  // 1. scheduled events
  while (next_event_ < params_.schedule.size() && params_.schedule[next_event_].cycle <= stats_.cycles) {
    const StateEvent& e = params_.schedule[next_event_++];
    model_.setState(e.state, e.quality, e.power);
    open_ = e.open;
  }
  // the KRL program ended on the RT PC's request (friStop): monitor mode, whatever the schedule says
  if (model_.stopRequested() && model_.state() == State::Cmd) model_.setState(State::Cmd, model_.quality(), model_.power());
  // 2. plant: outside CMD (or with the drives off) the robot holds its own set point.
  model_.holdUnlessCommanding(plant_->holdPose(plant_state_));
  plant_->step(model_.setPoint(), T, plant_state_);
  if (!open_) {
    // Closed interface: nothing sent, nothing taken; the cycle keeps its period.
    if (params_.real_time) {
      const double deadline = t0_ + double(stats_.cycles + 1) * T;
      for (double now = nowSeconds(); now < deadline; now = nowSeconds()) {
        std::size_t rn = 0;
        socket_.receive(in_.data(), in_.size(), rn, int64_t((deadline - now) * 1e6));  // a stray datagram is dropped
      }
    }
    ++stats_.closed_cycles;
    ++stats_.cycles;
    return;
  }
  // 3. measurement + faults
  buildMeasurement();
  std::size_t n = 0;
  encodeMeasurement(msr_, out_.data(), out_.size(), n);
  bool late = false;
  const bool expect_reply = sendWithFaults(n, late);
  const double t_sent = nowSeconds();
  // 4. wait for the reply
  const bool matched = awaitReply(t_sent, expect_reply);
  if (!matched) ++stats_.missed;
  // The KRC rates the link from this cycle's answer (the timing quality).
  model_.noteAnswer(matched, params_.real_time && matched ? cycle_latency_s_ : 0.0);
  syncStats();
  if (latency_log_ != nullptr) {
    sent_ring_[stats_.cycles % kLateWindow] =
        SentRecord{model_.sendSeq(), t_sent, latency_log_->size(), expect_reply};
    latency_log_->push_back(LatencySample{matched ? cycle_latency_s_ : std::nan(""), matched});
  }
  answer_rate_ = 0.99 * answer_rate_ + 0.01 * (matched ? 1.0 : 0.0);
  if (late) sendMeasurement(out_.data(), n);
  ++stats_.cycles;
}

void SimKrc::run(uint64_t cycles, const std::atomic<bool>* stop) {
  for (uint64_t i = 0; i < cycles; ++i) {
    if (stop != nullptr && stop->load(std::memory_order_relaxed)) break;
    runCycle();
  }
}

}  // namespace fri
}  // namespace tactile
