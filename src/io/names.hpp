#pragma once
/// What a name in a scenario (a body, a facet group) may hold: every name
/// ends up in the outputs and messages, which cannot carry every character.
#include <string>
#include <string_view>

namespace conserve::io {

/// The rule, as messages state it. history.csv's header names columns
/// "L_x:NAME" (no comma, quote or line break), a contact surface is written
/// "body:group" (no colon), and a message is one line (no control
/// character); spaces around a name would be invisible.
inline constexpr std::string_view kNameRule =
    "a name without ',', '\"', ':' or control characters and without leading or trailing spaces";

/// Why `name` breaks kNameRule, e.g. "'big, cube' contains ',' (a comma)"
/// or "contains U+000A (a control character)" (the name is not repeated
/// when it holds one); empty if it keeps the rule.
std::string name_problem(std::string_view name);

}  // namespace conserve::io
