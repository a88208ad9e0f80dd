// Compiled with -fno-exceptions -fno-rtti (see core/CMakeLists.txt): every core header must build the way a
// microcontroller build would, for double and float scalars.
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/newmark.hpp"
#include "rockwatch/core/response_oscillator.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/core/sensor_axes.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/core/fixed_math.hpp"
#include "rockwatch/core/fixed_point.hpp"
#include "rockwatch/core/fixed_point_eigen.hpp"
#include "rockwatch/core/fixed_point64.hpp"
#include "rockwatch/core/fixed_instability_indicators.hpp"
#include "rockwatch/core/fixed_rocking_stepper.hpp"
#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/instability_indicators.hpp"
#include "rockwatch/core/static_check.hpp"
#include "rockwatch/core/stepper_alarm_chain.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/core/wall_observer.hpp"
#include "rockwatch/core/observer/generated/observer_model.hpp"

template class rockwatch::core::RockingStepper<double>;
template class rockwatch::core::RockingStepper<float>;
template rockwatch::core::InstabilityConstants<double> rockwatch::core::cast_instability_constants<double>(
    const rockwatch::core::InstabilityConstants<double>&);
template rockwatch::core::InstabilityConstants<float> rockwatch::core::cast_instability_constants<float>(
    const rockwatch::core::InstabilityConstants<double>&);
template rockwatch::core::InstabilityIndicators<double> rockwatch::core::evaluate_instability<double>(
    const rockwatch::core::InstabilityConstants<double>&, const rockwatch::core::RockingStepper<double>&,
    const rockwatch::core::StepReport<double>&);
template rockwatch::core::InstabilityIndicators<float> rockwatch::core::evaluate_instability<float>(
    const rockwatch::core::InstabilityConstants<float>&, const rockwatch::core::RockingStepper<float>&,
    const rockwatch::core::StepReport<float>&);

// The fixed-point per-sample path (Q7.24): sensor mapping, Eigen products and the time-to-instability atanh.
namespace rockwatch::core::compile_check {
using Q7_24 = Fixed<7, 24>;
Eigen::Matrix<Q7_24, 2, 1> fixed_wall_inputs(const SensorAxes<Q7_24>& axes, const Eigen::Matrix<Q7_24, 3, 1>& s) {
  return wall_inputs(axes, s);
}
SensorAxes<Q7_24> fixed_default_sensor_axes() { return cast_sensor_axes<Q7_24>(default_sensor_axes()); }
SensorAxes<float> float_default_sensor_axes() { return cast_sensor_axes<float>(default_sensor_axes()); }
Q7_24 fixed_dot(const Eigen::Matrix<Q7_24, 3, 3>& m, const Eigen::Matrix<Q7_24, 3, 1>& v) { return (m * v).dot(v); }
Q7_24 fixed_time_to_instability_s(Fixed<1, 30> z, Q7_24 omega_radps) { return fixed_atanh<Q7_24>(z) / omega_radps; }
Q7_24 fixed_ln(Q7_24 u) { return fixed_log<Q7_24>(u); }
}  // namespace rockwatch::core::compile_check

// The fixed-point engine and its indicators (64-bit state, 128-bit intermediates on every target).
namespace rockwatch::core::compile_check {
FixedStepReport fixed_engine_step(FixedRockingStepper& s, AccelQ7_56 ug, AccelQ7_56 vg) { return s.step(ug, vg); }
FixedInstabilityIndicators fixed_indicators(const FixedInstabilityConstants& c, const FixedRockingStepper& s) {
  return evaluate_instability(c, s, FixedStepReport{});
}
}  // namespace rockwatch::core::compile_check

// The wall observer over both steppers, every member (its parts: core/observer/).
template class rockwatch::core::WallObserver<rockwatch::core::RockingStepper<double>>;
template class rockwatch::core::WallObserver<rockwatch::core::FixedRockingStepper>;

// The stepper → indicators → alarm chain over both steppers.
template class rockwatch::core::StepperAlarmChain<rockwatch::core::RockingStepper<double>>;
template class rockwatch::core::StepperAlarmChain<rockwatch::core::FixedRockingStepper>;
