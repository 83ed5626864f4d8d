// Numbers written as text (OBJ export): the shortest spelling of a double that reads back as the
// same double ({fmt}'s Dragonbox: "0.1", "1e+300", "-0"), and unsigned indices. Private to the core.
// snprintf("%.17g") took 0.6 us a number in WASM (4 s to write a 655k-vertex OBJ), and its 17
// digits spelt 0.1 as 0.10000000000000001.
#pragma once
#include <cstdint>

#include "fmt/compile.h"
#include "fmt/format.h"

namespace mrvol::text {

/** x at `at` (room for 32 characters); returns the end. */
inline char* writeShortest(char* at, double x) { return fmt::format_to(at, FMT_COMPILE("{}"), x); }

/** i in decimal at `at` (room for 10 characters); returns the end. */
inline char* writeUnsigned(char* at, uint32_t i) {
  char digits[10];
  int n = 0;
  do digits[n++] = char('0' + i % 10); while ((i /= 10) != 0);
  while (n > 0) *at++ = digits[--n];
  return at;
}

}  // namespace mrvol::text
