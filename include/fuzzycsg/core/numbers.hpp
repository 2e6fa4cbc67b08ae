#pragma once
// Printing numbers for people and files.

#include <string>

namespace fuzzycsg {

// The shortest decimal form that reads back to exactly `v` ("0.1", "1e+100", "5e-324", "-0"),
// or "nan", "inf", "-inf".
std::string shortest_number(double v);

}  // namespace fuzzycsg
