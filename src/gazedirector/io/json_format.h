#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace gazedirector {

// Indented JSON that keeps short numeric arrays (points, matrices rows) on one
// line, so that documents stay readable.
std::string PrettyJson(const nlohmann::json& value, int indent = 2);

// `value` rounded to `decimals` places, so that JSON prints it short.
double RoundTo(double value, int decimals);

// The JSON library's message without its "[json.exception.parse_error.101] "
// tag: "parse error at line 1, column 2: ...", for one-line errors.
std::string JsonErrorText(const nlohmann::json::exception& error);

}  // namespace gazedirector
