#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gazedirector/fit/fitter.h"

namespace gazedirector {

// The fitter's named options, settable as "name=value" (for example
// "truncation=0.2" or "iterations=24"); ListFitOptions() names them all.
void SetFitOption(FitOptions& options, const std::string& assignment);
std::vector<std::string> ListFitOptions();
// The options of eye-patch fits (`track --eye-patch`, `eval columbia`):
// kEyePatchWorkWidth, then `assignments` in order.
FitOptions EyePatchFitOptions(const std::vector<std::string>& assignments);
// Every named option's value (ListFitOptions' names as keys), for recording
// what a measurement ran with.
nlohmann::json FitOptionsToJson(const FitOptions& options);

}  // namespace gazedirector
