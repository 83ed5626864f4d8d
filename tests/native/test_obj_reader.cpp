// ObjReader (obj_reader.h): OBJ text fed in chunks gives what readObj gives for the whole text,
// wherever the chunks split it (mid-number, mid-CRLF, inside the byte order mark, mid-line), and
// the same error, with the same line number, for a bad file.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "mrvol/error.h"
#include "mrvol/mesh.h"
#include "mrvol/obj_reader.h"

using namespace mrvol;

namespace {

struct Read {
  TriangleMesh mesh;
  SourceLines lines;
  ObjExtras extras;
  std::string error;
};

Read whole(const std::string& text) {
  Read r;
  try {
    r.mesh = readObj(text, &r.lines, &r.extras);
  } catch (const Error& e) {
    r.error = e.what();
  }
  return r;
}

// The text fed in pieces that end at `cuts` (increasing offsets), the rest last.
Read chunked(const std::string& text, const std::vector<size_t>& cuts, size_t expected) {
  Read r;
  try {
    ObjReader reader(expected);
    size_t at = 0;
    for (size_t cut : cuts) reader.feed(std::string_view(text).substr(at, cut - at)), at = cut;
    reader.feed(std::string_view(text).substr(at));
    r.mesh = reader.finish(&r.lines, &r.extras);
  } catch (const Error& e) {
    r.error = e.what();
  }
  return r;
}

void expectSame(const Read& a, const Read& b, const std::string& where) {
  ASSERT_EQ(a.error, b.error) << where;
  EXPECT_EQ(a.mesh.positions, b.mesh.positions) << where;
  EXPECT_EQ(a.mesh.faces, b.mesh.faces) << where;
  EXPECT_EQ(a.lines.vertex, b.lines.vertex) << where;
  EXPECT_EQ(a.lines.face, b.lines.face) << where;
  EXPECT_EQ(a.extras.polygons, b.extras.polygons) << where;
  EXPECT_EQ(a.extras.polygonTriangles, b.extras.polygonTriangles) << where;
  EXPECT_EQ(a.extras.texCoords, b.extras.texCoords) << where;
  EXPECT_EQ(a.extras.normals, b.extras.normals) << where;
  EXPECT_EQ(a.extras.colors, b.extras.colors) << where;
  EXPECT_EQ(a.extras.cornerTexCoords, b.extras.cornerTexCoords) << where;
  EXPECT_EQ(a.extras.cornerNormals, b.extras.cornerNormals) << where;
}

// Every split into two pieces, every split into three around each offset, and one byte at a time;
// with and without the file's size known.
void expectSplitsAgree(const std::string& text) {
  const Read reference = whole(text);
  for (size_t expected : {size_t(0), text.size()}) {
    for (size_t cut = 0; cut <= text.size(); ++cut)
      expectSame(reference, chunked(text, {cut}, expected), "cut at " + std::to_string(cut));
    for (size_t cut = 1; cut + 1 < text.size(); ++cut)
      expectSame(reference, chunked(text, {cut - 1, cut + 1}, expected), "cuts around " + std::to_string(cut));
    std::vector<size_t> everyByte;
    for (size_t cut = 1; cut < text.size(); ++cut) everyByte.push_back(cut);
    expectSame(reference, chunked(text, everyByte, expected), "one byte at a time");
  }
}

}  // namespace

TEST(ObjReader, EverySplitOfAFileWithEveryFormEqualsTheWholeRead) {
  expectSplitsAgree(
      "\xEF\xBB\xBF# a comment\r\n"
      "v -0.47085295474687316 0.76185608448375686 1.7308149509183618e-17 \r\n"
      "v 1 0 0 0.5 0.25 0.125\r\n"
      "v\t+1.5e+0 1 0 1 1 1\n"
      "v 0 1 0 0 0 1   \n"
      "vt 0 0\nvt 1 0 0\nvn 0 0 1\n"
      "o thing\ng group\ns off\nusemtl m\n"
      "f 1/1/1 2/2/1 3//1\r\n"
      "f -4 -2 -1 # comment after\n"
      "f 2 4 3 1\n"
      "f 1 2 4");
}

TEST(ObjReader, EverySplitOfABadFileGivesTheSameLineInItsError) {
  for (const std::string text : {
           std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv 1.5x 0 0\n"),
           std::string("v 0 0 0\r\nv 1 0 0\rv 0 1 0\r\nf 1 2 3\r\n"),        // old Mac CR
           std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"),             // forward reference
           std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nmagic\x01 stuff\n"),  // binary
           std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\n"),                     // no faces
           std::string("\xEF\xBB"),                                          // part of a BOM: empty-ish
           std::string(""),
       }) {
    SCOPED_TRACE(text);
    ASSERT_FALSE(whole(text).error.empty());
    expectSplitsAgree(text);
  }
}

// OBJ's line continuation: a statement whose lines end in '\\' reads as one line (a comment's
// '\\' continues nothing), wherever the chunks split it; an error names the statement's first line.
TEST(ObjReader, ContinuedLinesReadAsOneStatement) {
  const std::string joined =
      "# C:\\models\\\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const std::string text =
      "# C:\\models\\\nv 0 0 \\\n0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 \\  \r\n  \\\n4\nf 1 4 3\nf 2\\\n 3 4\n";
  const Read reference = whole(joined);
  const Read continued = whole(text);
  ASSERT_EQ(continued.error, "");
  EXPECT_EQ(continued.mesh.positions, reference.mesh.positions);
  EXPECT_EQ(continued.mesh.faces, reference.mesh.faces);
  EXPECT_EQ(continued.lines.vertex, (std::vector<uint32_t>{2, 4, 5, 6}));
  EXPECT_EQ(continued.lines.face, (std::vector<uint32_t>{7, 8, 11, 12}));
  expectSplitsAgree(text);
  const std::string bad = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 \\\n2 \\\n9\n";
  EXPECT_EQ(whole(bad).error.rfind("line 4: ", 0), 0u) << whole(bad).error;
  expectSplitsAgree(bad);
  expectSplitsAgree("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 \\");  // the mark ends the file
}

TEST(ObjReader, ALineLongerThanAnyChunkIsKeptWhole) {
  std::string text = "# " + std::string(5000, 'x') + "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::vector<size_t> cuts;
  for (size_t cut = 7; cut < text.size(); cut += 7) cuts.push_back(cut);
  expectSame(whole(text), chunked(text, cuts, 0), "chunks of 7 bytes");
}

TEST(ObjReader, FinishesOnceAndTakesNothingAfter) {
  ObjReader reader;
  reader.feed("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(reader.finish().faceCount(), 1u);
  EXPECT_THROW(reader.feed("v 0 0 0\n"), Error);
  EXPECT_THROW(reader.finish(), Error);
}

// The one-pass reading of plain `v x y z` and `f a b c` lines (obj.cpp) against the general path:
// the same file with a blank before every line (which that pass never takes) reads the same, or
// fails with the same message. Random short files of near-plain lines: signs, exponents, comments,
// slashes, zero and over-long indices, inf / nan, tabs, CRLF, trailing blanks.
TEST(ObjReader, PlainLinesReadInOnePassEqualTheGeneralPath) {
  const char* tokens[] = {"1",   "2",    "3",  "-1",   "+1",   "0",         "01",         "1.5", "-.5", ".5",  "-",
                          "1e",  "1e5",  "1e400", "inf", "-nan", "1#",     "#",          "1/2", "2//3", "123456789",
                          "1234567890", "4", "5", "0x1", "1.0e-3", "-0", "1.", "abc", "1-2", "9e99", "1e101"};
  const char* keywords[] = {"v", "f", "vt", "vn", "v\t", "f\t", "#v", "o"};
  const size_t tokenCount = sizeof tokens / sizeof *tokens, keywordCount = sizeof keywords / sizeof *keywords;
  uint32_t state = 12345;
  auto next = [&](uint32_t n) {  // a fixed linear congruential sequence: the same files every run
    state = state * 1664525u + 1013904223u;
    return (state >> 8) % n;
  };
  size_t read = 0;
  for (int file = 0; file < 3000; ++file) {
    std::vector<std::string> lines = {"v 0 0 0", "v 1 0 0", "v 0 1 0", "v 0 0 1", "f 1 2 3", "vt 0 0"};
    for (uint32_t l = 0, n = 1 + next(4); l < n; ++l) {
      std::string line = keywords[next(keywordCount)];
      for (uint32_t k = 0, m = next(6); k < m; ++k)
        line += std::string(next(4) ? " " : "\t") + tokens[next(tokenCount)];
      if (next(5) == 0) line += " ";
      lines.push_back(line);
    }
    lines.push_back("f 1 2 4");
    std::string plain, general;
    for (const std::string& line : lines) {
      const char* end = next(6) == 0 ? "\r\n" : "\n";
      plain += line + end;
      general += " " + line + end;
    }
    const Read a = whole(plain), b = whole(general);
    expectSame(a, b, plain);
    read += a.error.empty();
  }
  EXPECT_GT(read, 200u);  // enough of the files are valid for their arrays to be compared
}
