// rockwatch.study (study_module.cpp): the statistics of `rockwatch study`, a submodule of the extension.
#pragma once

#include <pybind11/pybind11.h>

namespace rockwatch::python {

// Defines the submodule `study` of `parent`.
void add_study_module(pybind11::module_& parent);

}  // namespace rockwatch::python
