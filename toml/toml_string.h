// A text as a TOML basic string, quoted and escaped, for what the gateway writes into a
// configuration: a form's value (config/form_values.h), the demo's own file (app/).
#pragma once

#include <string>
#include <string_view>

namespace tiltgate::toml_input {

// "a \"b\"": quotes and backslashes escaped, control characters as \uXXXX.
std::string toml_string(std::string_view text);

}  // namespace tiltgate::toml_input
