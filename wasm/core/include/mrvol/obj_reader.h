// OBJ text read in chunks as they come (a file read piece by piece, never whole in memory): the
// same statements, checks and messages (with line numbers) as readObj (mesh.h), whatever the
// split (mid-number, mid-CRLF, mid-line, one byte at a time).
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

#include "mrvol/mesh.h"

namespace mrvol {

class ObjReader {
 public:
  // expectedBytes: the file's size when known (0: unknown), for progress (fraction()).
  explicit ObjReader(size_t expectedBytes = 0);
  ~ObjReader();
  ObjReader(const ObjReader&) = delete;
  ObjReader& operator=(const ObjReader&) = delete;

  // The next bytes of the file. Throws Error("line L: ...") as soon as a whole line is wrong, or
  // when the vertices and faces so far are already too many to open (checkMeshSize).
  void feed(std::string_view chunk);
  // The end of the file: the mesh, as readObj(text, lines, extras) of the concatenated chunks.
  TriangleMesh finish(SourceLines* lines = nullptr, ObjExtras* extras = nullptr);

  size_t bytesRead() const { return seen_; }
  double fraction() const { return expected_ > 0 ? double(seen_) / double(expected_) : 0.0; }

  struct Parser;  // the reading state, shared with readObj

 private:
  void take(std::string_view chunk);
  std::unique_ptr<Parser> parser_;
  std::string partial_;  // an unfinished last line (or the first bytes, until the BOM is known)
  size_t expected_ = 0, seen_ = 0;
  bool bomChecked_ = false, finished_ = false;
};

}  // namespace mrvol
