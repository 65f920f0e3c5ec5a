// The reference the report writers' number formats are tested against: printf("%.*f"), the
// format every report column is documented in, with the writers' one rule on top (no "-0").
#pragma once

#include <cstdio>
#include <string>

namespace rcsim::test {

inline std::string printf_fixed(double v, int decimals) {
    char buf[400]; // DBL_MAX in fixed notation is 309 digits
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    std::string s = buf;
    if (s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
    return s;
}

} // namespace rcsim::test
