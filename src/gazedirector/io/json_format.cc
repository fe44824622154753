#include "gazedirector/io/json_format.h"

#include <cmath>

namespace gazedirector {
namespace {

// Arrays of scalars, and small matrices (up to 4 rows of scalars), print flat.
bool IsFlat(const nlohmann::json& value) {
  if (!value.is_array()) return false;
  bool nested = false;
  for (const auto& element : value) {
    if (element.is_object()) return false;
    if (element.is_array()) {
      nested = true;
      for (const auto& inner : element) {
        if (inner.is_structured()) return false;
      }
    }
  }
  return !nested || value.size() <= 4;
}

void Write(const nlohmann::json& value, int indent, int depth, std::string& out) {
  const std::string pad(static_cast<std::size_t>(indent * (depth + 1)), ' ');
  const std::string close_pad(static_cast<std::size_t>(indent * depth), ' ');
  if (value.is_object() && !value.empty()) {
    out += "{\n";
    std::size_t i = 0;
    for (const auto& [key, element] : value.items()) {
      out += pad + nlohmann::json(key).dump() + ": ";
      Write(element, indent, depth + 1, out);
      out += ++i < value.size() ? ",\n" : "\n";
    }
    out += close_pad + "}";
  } else if (value.is_array() && !value.empty() && !IsFlat(value)) {
    out += "[\n";
    for (std::size_t i = 0; i < value.size(); ++i) {
      out += pad;
      Write(value[i], indent, depth + 1, out);
      out += i + 1 < value.size() ? ",\n" : "\n";
    }
    out += close_pad + "]";
  } else {
    std::string flat = value.dump();
    // A single space after commas reads better in long flat arrays.
    std::string spaced;
    bool in_string = false;
    for (char c : flat) {
      spaced += c;
      if (c == '"') in_string = !in_string;
      if (c == ',' && !in_string) spaced += ' ';
    }
    out += spaced;
  }
}

}  // namespace

std::string PrettyJson(const nlohmann::json& value, int indent) {
  std::string out;
  Write(value, indent, 0, out);
  return out;
}

double RoundTo(double value, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(value * scale) / scale;
}

std::string JsonErrorText(const nlohmann::json::exception& error) {
  const std::string text = error.what();
  const auto tag_end = text.find("] ");
  return text.rfind("[json.exception.", 0) == 0 && tag_end != std::string::npos ? text.substr(tag_end + 2) : text;
}

}  // namespace gazedirector
