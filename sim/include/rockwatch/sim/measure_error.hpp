// The error the record measures (response spectra, intensity measures) throw for input they cannot measure: an
// empty record, a non-finite sample, dt ≤ 0, invalid periods or damping. The message says which and where.
#pragma once

#include <stdexcept>

namespace rockwatch::sim {

class MeasureError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace rockwatch::sim
