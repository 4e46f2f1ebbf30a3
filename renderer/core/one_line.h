// Text from a library (OCIO, OIIO) or a user (camera names) made fit for a one-line error message
// or a one-line header field: line breaks become spaces, trailing spaces go.
#pragma once

#include <algorithm>
#include <string>

namespace veach {

inline std::string one_line(std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    std::replace(s.begin(), s.end(), '\r', ' ');
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

}  // namespace veach
