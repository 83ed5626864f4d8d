// Shared by the mesh file readers (read_*.cpp, io_formats.cpp): byte access, numbers in
// messages, coordinate checks, a whitespace tokenizer for the text formats. Private to the core.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <system_error>

#include "fast_float.h"

#include "mrvol/error.h"

namespace mrvol::io {

// 1234567 -> "1,234,567": counts and offsets in messages.
inline std::string count(uint64_t n) {
  std::string digits = std::to_string(n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out.push_back(',');
    out.push_back(digits[i]);
  }
  return out;
}

// "its 1 face repeats" / "each of its 5 faces repeats": why no face of a file has an area.
inline std::string eachFaceRepeats(uint64_t faces, const char* what = "faces") {
  std::string noun(what);
  if (faces == 1) return "its one " + noun.substr(0, noun.size() - 1) + " repeats a vertex";
  return "each of its " + count(faces) + " " + noun + " repeats a vertex";
}

// A token quoted for a message: at most 40 characters, control and non-ASCII bytes as '?'.
inline std::string quoted(std::string_view token) {
  std::string s(token.substr(0, 40));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return "'" + s + (token.size() > 40 ? "...'" : "'");
}

// Coordinates beyond this would overflow the volume's triple products (as for OBJ).
constexpr double kMaxCoordinate = 1e100;

inline bool coordinateOk(double x) { return std::isfinite(x) && std::fabs(x) <= kMaxCoordinate; }

inline std::string coordinateProblem(double x) {
  return std::isfinite(x) ? "is too large (mrvol accepts |x| <= 1e100 so that volumes stay finite)" : "is not finite";
}

// Unaligned little- or big-endian loads.
template <class T>
T load(const char* p, bool bigEndian = false) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (bigEndian)
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  T value;
  std::memcpy(&value, b, sizeof(T));
  return value;
}

// Whether text starts with a UTF-8 byte order mark (EF BB BF).
inline bool hasByteOrderMark(std::string_view b) { return b.substr(0, 3) == "\xEF\xBB\xBF"; }

// Text formats (ASCII STL, PLY, OFF): line by line, tokens split by blanks.
inline bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// Whether `text` is `word` (ASCII letters, given in lower case) in any case: ASCII STL's keywords
// are written SOLID, Solid or solid by different tools.
inline bool equalsWord(std::string_view text, std::string_view word) {
  if (text.size() != word.size()) return false;
  for (size_t i = 0; i < word.size(); ++i)
    if ((text[i] | 0x20) != word[i]) return false;
  return true;
}

// A polygon's corners with each run of the same vertex (cyclically: the last and the first too)
// kept once: "a b c c", a triangle some writers pad to a quad, is the triangle a b c. In place.
template <class Corners>
void dropRepeatedCorners(Corners& polygon) {
  size_t n = 0;
  for (size_t k = 0; k < polygon.size(); ++k)
    if (n == 0 || polygon[k] != polygon[n - 1]) polygon[n++] = polygon[k];
  while (n > 1 && polygon[n - 1] == polygon[0]) --n;
  polygon.resize(n);
}

// Bytes no text holds (NUL, controls other than blanks and line breaks): a binary file's.
inline bool hasBinaryBytes(std::string_view b) {
  for (char c : b) {
    unsigned char u = static_cast<unsigned char>(c);
    if (u == 0 || (u < 32 && !isBlank(c) && c != '\n')) return true;
  }
  return false;
}

// Whether `text`, after its leading blanks and line breaks, starts with `word` (any case).
inline bool startsWithWord(std::string_view text, std::string_view word) {
  size_t i = 0;
  while (i < text.size() && (isBlank(text[i]) || text[i] == '\n')) ++i;
  return equalsWord(text.substr(i, word.size()), word);
}

class LineReader {
 public:
  explicit LineReader(std::string_view text, size_t start = 0, size_t firstLine = 1)
      : text_(text), pos_(start), line_(firstLine - 1) {}
  // The next line without its end of line; false at the end.
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    size_t eol = text_.find('\n', pos_);
    if (eol == std::string_view::npos) eol = text_.size();
    line = text_.substr(pos_, eol - pos_);
    pos_ = eol + 1;
    ++line_;
    return true;
  }
  size_t line() const { return line_; }
  size_t offset() const { return pos_; }
  size_t remaining() const { return pos_ < text_.size() ? text_.size() - pos_ : 0; }

 private:
  std::string_view text_;
  size_t pos_;
  size_t line_;
};

// Splits a line into at most `max` tokens; returns how many (more are counted, not stored).
inline size_t tokenize(std::string_view line, std::string_view* tokens, size_t max) {
  size_t n = 0, i = 0;
  while (i < line.size()) {
    while (i < line.size() && isBlank(line[i])) ++i;
    size_t j = i;
    while (j < line.size() && !isBlank(line[j])) ++j;
    if (j > i) {
      if (n < max) tokens[n] = line.substr(i, j - i);
      ++n;
    }
    i = j;
  }
  return n;
}

// Decimal number (as the OBJ reader reads them: fast_float, in place, a leading '+' allowed; inf
// and nan read as such for the callers to refuse by name); false when the token is not one number.
// strtod was 10-20 times slower here (ASCII PLY, OFF and STL read at ~12 MB/s).
inline bool parseDouble(std::string_view token, double& value) {
  if (token.empty() || token.size() >= 64) return false;
  const char* first = token.data();
  const char* last = first + token.size();
  if (*first == '+' && last - first > 1 && first[1] != '-' && first[1] != '+') ++first;
  const auto result = fast_float::from_chars(first, last, value);
  return result.ec == std::errc() && result.ptr == last;
}

// Non-negative decimal integer up to `max`; false otherwise.
inline bool parseUnsigned(std::string_view token, uint64_t max, uint64_t& value) {
  if (token.empty() || token.size() > 20) return false;
  size_t i = token[0] == '+' ? 1 : 0;
  if (i == token.size()) return false;
  value = 0;
  for (; i < token.size(); ++i) {
    char c = token[i];
    if (c < '0' || c > '9') return false;
    value = value * 10 + uint64_t(c - '0');
    if (value > max) return false;
  }
  return true;
}

// What a file that is not the expected format looks like, from its first bytes ("" when unknown):
// " (looks like a ZIP archive)".
std::string looksLike(std::string_view bytes);

}  // namespace mrvol::io
