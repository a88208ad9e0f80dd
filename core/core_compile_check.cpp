// Compiled with -fno-exceptions -fno-rtti (see core/CMakeLists.txt): every core header must build the way a
// microcontroller build would, for double and float scalars.
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/newmark.hpp"
#include "rockwatch/core/response_oscillator.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/rocking_stepper.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/core/static_check.hpp"
#include "rockwatch/core/wall.hpp"

template class rockwatch::core::RockingStepper<double>;
template class rockwatch::core::RockingStepper<float>;
