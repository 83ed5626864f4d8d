// Errors of the core: one exception type whose message names what is wrong and where.
#pragma once
#include <stdexcept>
#include <string>

namespace mrvol {

// Every failure the core reports to a caller. The message is meant for the user as it is
// ("line 12: face refers to vertex 40 but the file has 38 vertices").
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace mrvol
