// The wall observer: fuses wall-mounted sensors (SPEC §8) with the rocking model so that the monitor follows the
// real wall, not a nominal one running open loop on the ground motion.
//
// A hybrid extended Kalman filter on z = (x, ẋ, e, b, κc, κk):
//   x, ẋ   the mid-height hinge displacement and velocity [m, m/s]; their mean IS the rocking stepper's state (the
//          stepper propagates it with its impacts, start and rest logic; the observer corrects it after each step);
//   e      √r, the velocity ratio at impact [-] (r̂ = ê², fed back into the stepper after every correction);
//   b      the zero offset of the displacement transducer [m];
//   κc, κk multiplicative corrections to the nominal wall's capacity c_s and stiffness k (SPEC §9: ẍ = −γü − s·c_s
//          + k·x on side s, divided by p1), prior 1 ± capacity_sigma0 each; the stepper propagates the mean with
//          κc·c_s and κk·k (set_capacity_scales after every correction), so x_inst = κc/κk·x_inst,nominal,
//          ω = √(κk·k), the energy barrier per unit p1 (κc c_s)²/(2 κk k). Estimates leaving the physical range
//          (κ outside [0.25, 4], κc/κk outside [0.3, 2], e outside [0, 1]) are clamped and flagged (estimate_clamped).
// Between impacts the covariance follows the linearised model of the current side (the stepper's own Newmark step
// with the estimated stiffness κk·k_s, k_s = p4/p1 at ü = 0, G = g) with white model-acceleration noise; the columns
// of κc and κk are the derivatives of that Newmark step: with f_c = ∂ẍ/∂κc = −s·c_s, D = 1 + h²κk k_s/4,
//   ∂x₁/∂κc = h² f_c/(2D),  ∂ẋ₁/∂κc = h/2·(2 f_c − κk k_s ∂x₁/∂κc),
//   ∂x₁/∂κk = −h² k_s (x₀ + x₁)/(4D),  ∂ẋ₁/∂κk = h/2·(−k_s (x₀ + x₁) − κk k_s ∂x₁/∂κk). At an impact it
// follows the impact map through its saltation matrix: the guard is x = 0 and the reset ẋ⁺ = e·ẋ⁻, so
//   δx⁺ = e δx⁻,  δẋ⁺ = (a⁺ − e a⁻)/ẋ⁻ · δx⁻ + e δẋ⁻ + ẋ⁻ δe
// (a∓ the accelerations on the two sides at the hinge). The ẋ⁻ δe term is what makes r identifiable: the motion
// after an impact measures e. At rest the state is known (x = ẋ = 0), so a displacement reading there measures
// only the bias: the zero-offset estimate comes from the rests.
// Measurements (SPEC §8): the displacement transducer x_mid = x + b + noise (H = [1 0 0 1]); the accelerometer at
// the hinge on block 1, a_mid = ü + ẍ − G·x/h1 with ẍ = f − k x on the current side (H = [−(k_s + g/h1) 0 0 0]),
// used only while rocking and not in a step with an impact (the impact is a spike, SPEC §8). Every innovation is
// gated by χ² (1 degree of freedom); consecutive rejections while the ground shakes re-initialise the motion from
// the measurement (the real wall rocks where the model does not, or the sensor came back after a dropout).
//
// Time alignment: sensor samples are queued (fixed ring) with their utime and applied after the ground step whose
// time reaches theirs — never before (a future sample is never used) — extrapolated to the step end by ẋ̂·age.
// Samples older than max_age are dropped (stale); older than one step are applied but flagged (misaligned). At most
// one sample per step (the newest due; older due ones are passed over, counted superseded: SPEC §8, issue 44), so a
// step's work is bounded whatever arrived.
//
// Scalar: the stepper's (ObserverStepperTraits): double for core::RockingStepper<double>, ObserverQ10_53 for the
// fixed-point stepper (the state e, b, κc, κk, the innovations); Cov, the covariance's, gains' and linearisations':
// double, and single precision for the fixed-point stepper (the M4F's FPU; -ffp-contract=off). Core rules:
// header-only, no heap, no exceptions, no I/O; init() is initialisation-time code (double), the rest is bounded work
// (at most kQueueCapacity updates per step, each a few 6 × 6 products).
//
// The files, laid out like PX4's EKF2 (this header is the one to include; it includes them all):
//   observer/observer_options.hpp      ObserverOptions, ObserverError, validate_observer_options
//   observer/observer_types.hpp        WallSensorSample, observer_flag, ObserverCounters, ObserverStepReport, …
//   observer/stepper_traits.hpp        how the observer reads and corrects each stepper; its Scalar and Cov
//   observer/wall_observer_class.hpp   class WallObserver: init, push, the step's pieces, the published estimates
//   observer/prediction.hpp            the covariance through a step (Newmark transition, saltation, rest)
//   observer/fusion_update.hpp         the scalar update and χ² gate every sensor shares; the correction fed back
//   observer/displacement_fusion.hpp   x_mid: H, innovation, gate          observer/displacement_control.hpp: when
//                                      to fuse (stuck), rejections (fault, quiet motion, re-initialisation), loss,
//                                      model doubt
//   observer/acceleration_fusion.hpp   a_mid: H, innovation, gate          observer/acceleration_control.hpp: when
//                                      to fuse (rocking, no impact), capacity re-open, rest votes
#pragma once
#pragma once

#include "rockwatch/core/observer/observer_options.hpp"
#include "rockwatch/core/observer/observer_types.hpp"
#include "rockwatch/core/observer/stepper_traits.hpp"
#include "rockwatch/core/observer/wall_observer_class.hpp"
#include "rockwatch/core/observer/prediction.hpp"
#include "rockwatch/core/observer/fusion_update.hpp"
#include "rockwatch/core/observer/displacement_fusion.hpp"
#include "rockwatch/core/observer/displacement_control.hpp"
#include "rockwatch/core/observer/acceleration_fusion.hpp"
#include "rockwatch/core/observer/acceleration_control.hpp"
