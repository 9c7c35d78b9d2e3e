// One servo step (target <= 2 us) against a naive dynamic-size Eigen
// (MatrixXd/VectorXd, allocating per call) implementation of the same
// Eq. 7-13 chain, measured in the same run.
#include <benchmark/benchmark.h>

#include <Eigen/Dense>
#include <kdl/frames.hpp>

#include "tactile_servo/program_io.hpp"
#include "tactile_servo/servo.hpp"

using namespace tactile;

namespace {

ContactFeatures features(double t) {
  ContactFeatures f;
  f.time_s = t;
  f.cop_x = 0.002;
  f.cop_y = -0.001;
  f.coc_x = 0.001;
  f.coc_y = -0.0005;
  f.dzmp_x = -0.0005;
  f.dzmp_y = 0.001;
  f.alpha_z = 0.05;
  f.d_z = 0.0025;
  f.force = 4.5;
  f.contact = ContactType::Edge;
  f.status = FeatureStatus::Ok;
  return f;
}

Pose pose() {
  Pose p;
  p.p = {0.5, 0.1, 0.3};
  KDL::Rotation::RPY(3.1, 0.1, 0.2).GetQuaternion(p.q[0], p.q[1], p.q[2], p.q[3]);
  return p;
}

void BM_ServoStep(benchmark::State& state) {
  ServoParams p;
  if (!loadServoProgram(std::string(TACTILE_SERVO_PROGRAM_DIR) + "/bent_bar.yaml", p).ok()) {
    state.SkipWithError("cannot load bent_bar.yaml");
    return;
  }
  p.pose_update = PoseUpdate::Measured;  // same start pose every cycle: steady state
  TactileServo s;
  s.configure(p);
  ServoInput in;
  in.flange_measured = pose();
  ServoOutput out;
  double t = 0;
  for (auto _ : state) {
    t += 0.01;
    in.time_s = t;
    in.features = features(t);
    benchmark::DoNotOptimize(s.step(in, 0.01, out));
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_ServoStep);

// Naive: the same chain (Eq. 7, 8, 9, 13 PI + motion sign + step limits,
// Eq. 13 KDL transform, Eq. 12 update) with dynamic-size Eigen objects built
// per call, as a straightforward first implementation would do.
struct Naive {
  Eigen::VectorXd sd = Eigen::VectorXd::Zero(6), kp = Eigen::VectorXd::Constant(6, 0.03),
                  ki = Eigen::VectorXd::Constant(6, 0.02), integral = Eigen::VectorXd::Zero(6),
                  sign = Eigen::VectorXd::Zero(6);
  KDL::Frame T_es = KDL::Frame(KDL::Vector(0, 0, 0.03));
  Naive() { sign << -1, -1, 1, 1, -1, -1; }
  Pose step(const ContactFeatures& f, const Pose& x_a, double dt) {
    Eigen::VectorXd s(6);
    s << f.cop_x, f.cop_y, f.d_z, f.coc_x, f.coc_y, f.alpha_z;
    const double beta = f.contact == ContactType::Edge ? 1.0 : 0.0;
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6, 6);
    J(0, 0) = J(1, 1) = J(2, 2) = J(3, 1) = J(4, 0) = 1.0;
    J(3, 4) = J(4, 3) = -beta;
    J(5, 5) = beta;
    Eigen::MatrixXd P = Eigen::MatrixXd::Identity(6, 6);
    P(3, 3) = 0;
    const Eigen::VectorXd ds = sd - J * s;       // Eq. 7
    const Eigen::VectorXd task = P * ds;         // Eq. 9
    integral += task * dt;
    Eigen::VectorXd u = sign.cwiseProduct(kp.cwiseProduct(task) + ki.cwiseProduct(integral));  // Eq. 13
    const double nt = u.head(3).norm(), nr = u.tail(3).norm();
    if (nt > 0.0005) u.head(3) *= 0.0005 / nt;
    if (nr > 0.0087) u.tail(3) *= 0.0087 / nr;
    const KDL::Frame T_ge(KDL::Rotation::Quaternion(x_a.q[0], x_a.q[1], x_a.q[2], x_a.q[3]),
                          KDL::Vector(x_a.p[0], x_a.p[1], x_a.p[2]));
    const KDL::Frame T_gs = T_ge * T_es;
    const KDL::Twist tg = T_gs.M * KDL::Twist(KDL::Vector(u(0), u(1), u(2)), KDL::Vector(u(3), u(4), u(5)));
    const KDL::Frame T = KDL::addDelta(T_gs, tg, 1.0) * T_es.Inverse();  // Eq. 12
    Pose out;
    out.p = {T.p.x(), T.p.y(), T.p.z()};
    T.M.GetQuaternion(out.q[0], out.q[1], out.q[2], out.q[3]);
    return out;
  }
};

void BM_NaiveDynamicChain(benchmark::State& state) {
  Naive n;
  const Pose x = pose();
  double t = 0;
  for (auto _ : state) {
    t += 0.01;
    benchmark::DoNotOptimize(n.step(features(t), x, 0.01));
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_NaiveDynamicChain);

}  // namespace

BENCHMARK_MAIN();
