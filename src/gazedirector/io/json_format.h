#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace gazedirector {

// Indented JSON that keeps short numeric arrays (points, matrices rows) on one
// line, so that documents stay readable.
std::string PrettyJson(const nlohmann::json& value, int indent = 2);

// `value` rounded to `decimals` places, so that JSON prints it short.
double RoundTo(double value, int decimals);

}  // namespace gazedirector
