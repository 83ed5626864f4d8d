// Hostile and malformed OBJ files (tests/data/bad): each must fail with the message its manifest
// (tests/data/bad/expected.json) expects, at the stage it expects; every .obj there must be listed.
// Accepted-but-odd files (tests/data/good) must read exactly like the plain octahedron.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "fixtures.h"
#include "mrvol/error.h"
#include "mrvol/hierarchy.h"
#include "mrvol/mesh.h"
#include "mrvol/multires_mesh.h"

using namespace mrvol;
namespace fs = std::filesystem;

namespace {

const std::string kBadDir = fixtures::sourcePath("tests/data/bad");
const std::string kGoodDir = fixtures::sourcePath("tests/data/good");

struct Expectation {
  std::string stage;  // "read" or "validate"
  std::string error;  // substring of the core's message
  std::string errorWithLines;  // validation given the OBJ lines of vertices and faces
};

// Just enough JSON for the manifest: objects, arrays, strings (with escapes), numbers, literals.
class ManifestParser {
 public:
  explicit ManifestParser(std::string text) : s_(std::move(text)) {}

  std::map<std::string, Expectation> parse() {
    std::map<std::string, Expectation> out;
    object([&](const std::string& key) {
      if (key != "files") return skipValue();
      object([&](const std::string& file) {
        Expectation e;
        object([&](const std::string& field) {
          if (field == "stage") e.stage = string();
          else if (field == "error") e.error = string();
          else if (field == "errorWithLines") e.errorWithLines = string();
          else skipValue();
        });
        if (!out.emplace(file, e).second) fail("file listed twice: " + file);
      });
    });
    ws();
    if (i_ != s_.size()) fail("trailing characters");
    return out;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error("expected.json, offset " + std::to_string(i_) + ": " + what);
  }
  void ws() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\n' || s_[i_] == '\r' || s_[i_] == '\t')) ++i_;
  }
  void expect(char c) {
    ws();
    if (i_ >= s_.size() || s_[i_] != c) fail(std::string("expected '") + c + "'");
    ++i_;
  }
  bool peek(char c) {
    ws();
    return i_ < s_.size() && s_[i_] == c;
  }
  template <class F>
  void object(F&& member) {
    expect('{');
    if (peek('}')) return void(++i_);
    do {
      std::string key = string();
      expect(':');
      member(key);
    } while (peek(',') && ++i_);
    expect('}');
  }
  std::string string() {
    expect('"');
    std::string out;
    while (i_ < s_.size() && s_[i_] != '"') {
      char c = s_[i_++];
      if (c != '\\') {
        out += c;
        continue;
      }
      if (i_ >= s_.size()) fail("unterminated escape");
      char e = s_[i_++];
      switch (e) {
        case 'n': out += '\n'; break;
        case 't': out += '\t'; break;
        case 'r': out += '\r'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'u': {
          if (i_ + 4 > s_.size()) fail("short \\u escape");
          unsigned code = unsigned(std::stoul(s_.substr(i_, 4), nullptr, 16));
          i_ += 4;
          if (code >= 0x80) fail("non-ASCII \\u escape");  // the manifest needs none
          out += char(code);
          break;
        }
        default: out += e;  // \" \\ \/
      }
    }
    expect('"');
    return out;
  }
  void skipValue() {
    ws();
    if (peek('{')) return object([&](const std::string&) { skipValue(); });
    if (peek('"')) return void(string());
    if (peek('[')) {
      ++i_;
      if (peek(']')) return void(++i_);
      do skipValue();
      while (peek(',') && ++i_);
      return expect(']');
    }
    size_t start = i_;
    while (i_ < s_.size() && std::string_view(",}] \n\r\t").find(s_[i_]) == std::string_view::npos) ++i_;
    if (i_ == start) fail("expected a value");
  }

  std::string s_;
  size_t i_ = 0;
};

const std::map<std::string, Expectation>& manifest() {
  static const std::map<std::string, Expectation> m = [] {
    std::string text = fixtures::readFile(kBadDir + "/expected.json");
    if (text.empty()) return std::map<std::string, Expectation>{};
    return ManifestParser(text).parse();
  }();
  return m;
}

std::vector<std::string> objFiles(const std::string& dir) {
  std::vector<std::string> names;
  if (!fs::is_directory(dir)) return names;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().extension() == ".obj") names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> manifestNames() {
  std::vector<std::string> names;
  try {
    for (const auto& [name, e] : manifest()) names.push_back(name);
  } catch (const std::exception&) {
    // Reported by BadInput.ManifestListsEveryFile.
  }
  return names;
}

std::string testName(const testing::TestParamInfo<std::string>& info) {
  std::string s = info.param.substr(0, info.param.size() - 4);  // without .obj
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

// The message of the mrvol::Error `f` throws; fails the test when it throws nothing or something else.
template <class F>
std::string errorOf(F&& f, const std::string& what) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << " threw a std::exception that is no mrvol::Error: " << e.what();
    return {};
  }
  ADD_FAILURE() << what << " threw nothing";
  return {};
}

// A message for a user: one line of printable ASCII.
void expectOneCleanLine(const std::string& message) {
  EXPECT_FALSE(message.empty());
  for (char c : message)
    EXPECT_TRUE(c >= 32 && c <= 126) << "byte " << int(static_cast<unsigned char>(c)) << " in: " << message;
}

}  // namespace

// ---- the manifest -------------------------------------------------------------------------------

TEST(BadInput, ManifestListsEveryFile) {
  const std::map<std::string, Expectation>* m = nullptr;
  ASSERT_NO_THROW(m = &manifest());
  ASSERT_GE(m->size(), 32u) << "tests/data/bad/expected.json is missing or lists too few files";
  auto files = objFiles(kBadDir);
  for (const auto& f : files) EXPECT_TRUE(m->count(f)) << f << " is in tests/data/bad but not in expected.json";
  for (const auto& [name, e] : *m) {
    EXPECT_TRUE(std::binary_search(files.begin(), files.end(), name)) << name << " is in expected.json but not on disk";
    EXPECT_TRUE(e.stage == "read" || e.stage == "validate") << name << ": stage '" << e.stage << "'";
    EXPECT_FALSE(e.error.empty()) << name << " has no expected error";
  }
}

// ---- every bad file -----------------------------------------------------------------------------

class BadFile : public testing::TestWithParam<std::string> {};

TEST_P(BadFile, FailsWithTheExpectedMessage) {
  const std::string name = GetParam();
  const Expectation& expected = manifest().at(name);
  const std::string text = fixtures::readFile(kBadDir + "/" + name);
  if (expected.stage == "read") {
    std::string message = errorOf([&] { readObj(text); }, "readObj");
    EXPECT_NE(message.find(expected.error), std::string::npos) << "got:      " << message << "\nexpected: " << expected.error;
    expectOneCleanLine(message);
    return;
  }
  TriangleMesh mesh;
  SourceLines lines;
  try {
    mesh = readObj(text, &lines);
  } catch (const Error& e) {
    FAIL() << "expected the file to read and fail validation, but readObj threw: " << e.what();
  }
  std::string message = errorOf([&] { validateMesh(mesh); }, "validateMesh");
  EXPECT_NE(message.find(expected.error), std::string::npos) << "got:      " << message << "\nexpected: " << expected.error;
  expectOneCleanLine(message);
  // What the bindings and the CLI call: the same error, before any hierarchy detection runs.
  std::string multires = errorOf([&] { MultiresMesh m(mesh); }, "MultiresMesh");
  EXPECT_EQ(multires, message);
  std::string detect = errorOf([&] { Hierarchy::detect(mesh); }, "Hierarchy::detect");
  EXPECT_EQ(detect, message);
  // Given the OBJ lines, the same message names each vertex's and face's line too.
  ASSERT_FALSE(expected.errorWithLines.empty()) << name << ": expected.json gives no errorWithLines";
  std::string withLines = errorOf([&] { MultiresMesh m(mesh, 16, &lines); }, "MultiresMesh with lines");
  EXPECT_NE(withLines.find(expected.errorWithLines), std::string::npos) << "got:      " << withLines << "\nexpected: " << expected.errorWithLines;
  EXPECT_NE(withLines.find("(line "), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(BadInput, BadFile, testing::ValuesIn(manifestNames()), testName);

// ---- the 10^6-face file: read linearly, duplicates found by sorting -----------------------------

TEST(BadInput, MillionDuplicateFacesAreRejectedQuickly) {
  const std::string text = fixtures::readFile(kBadDir + "/duplicate-face-1e6-times.obj");
  ASSERT_GT(text.size(), 8'000'000u);
  auto start = std::chrono::steady_clock::now();
  TriangleMesh mesh = readObj(text);
  double readSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(mesh.faceCount(), 1'000'000u);
  std::string message = errorOf([&] { validateMesh(mesh); }, "validateMesh");
  double totalSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NE(message.find("face 0 and face 1 are duplicates"), std::string::npos) << message;
  RecordProperty("read_ms", int(readSeconds * 1000));
  RecordProperty("total_ms", int(totalSeconds * 1000));
  std::printf("[          ] 10^6 duplicate faces: read %.0f ms, rejected after %.0f ms\n", readSeconds * 1e3,
              totalSeconds * 1e3);
  // About 0.2 s in a release build. Times are printed, not bounded (a shared machine makes a bound
  // flaky); anything quadratic (10^12 pair comparisons) would run into ctest's per-test timeout.
}

// ---- accepted-but-odd files ---------------------------------------------------------------------

TEST(GoodInput, EveryVariantReadsLikeThePlainOctahedron) {
  const TriangleMesh reference = readObj(fixtures::readFile(kGoodDir + "/octahedron.obj"));
  ASSERT_EQ(reference.vertexCount(), 6u);
  ASSERT_EQ(reference.faceCount(), 8u);
  EXPECT_EQ(reference.positions, fixtures::octahedron().positions);
  EXPECT_EQ(reference.faces, fixtures::octahedron().faces);
  auto files = objFiles(kGoodDir);
  ASSERT_GE(files.size(), 8u);
  for (const auto& name : files) {
    SCOPED_TRACE(name);
    TriangleMesh mesh;
    try {
      mesh = readObj(fixtures::readFile(kGoodDir + "/" + name));
    } catch (const Error& e) {
      ADD_FAILURE() << "readObj threw: " << e.what();
      continue;
    }
    EXPECT_EQ(mesh.positions, reference.positions);
    EXPECT_EQ(mesh.faces, reference.faces);
    try {
      MultiresMesh m(mesh);
      EXPECT_TRUE(m.topology().closed);
      EXPECT_NEAR(m.info(mesh.positions).volume, 4.0 / 3.0, 1e-15);
    } catch (const Error& e) {
      ADD_FAILURE() << "MultiresMesh threw: " << e.what();
    }
  }
}
