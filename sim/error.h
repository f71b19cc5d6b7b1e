// Errors that bad input raises. The `plausible` command turns an InputError
// into exit code 2 with its message; nothing in sim/ prints or exits.
#pragma once

#include <stdexcept>
#include <string>

namespace sim {

// A description or a step parameter that cannot be simulated: a negative mass,
// dt <= 0, a spring from a particle to itself. The message names the offending
// item and value, e.g. "particles[3].mass must be > 0 (got -1)".
class InputError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

// Formats a double the way messages quote values: shortest round-trip form.
std::string format_value(double value);

// The checks every description repeats. They throw InputError worded
// "<name> must be > 0 and finite, in <unit> (got <value>)" (no ", in" part
// when unit is empty).
void require_positive(double value, const std::string& name, const std::string& unit);
void require_nonnegative(double value, const std::string& name, const std::string& unit);

}  // namespace sim
