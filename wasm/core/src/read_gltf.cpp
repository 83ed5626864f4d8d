// glTF 2.0: .gltf (JSON, buffers as data: URIs or sidecar files given by the caller) and GLB
// (binary container: JSON chunk, BIN chunk). Every mesh of the default scene, node transforms
// applied (matrix or TRS), triangle primitives (indexed or not; strips and fans converted, their
// degenerate joining triangles dropped); points and lines are refused. Each primitive contributes
// the vertices its triangles use; seams (vertices split for normals or texture coordinates) are
// welded by exact position. JSON through nlohmann/json.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gltf_document.h"
#include "io_common.h"
#include "mrvol/io_formats.h"

namespace mrvol {

namespace gltf {

using io::count;

constexpr Matrix kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Matrix multiply(const Matrix& a, const Matrix& b) {
  Matrix c{};
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 4; ++row) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[k * 4 + row] * b[col * 4 + k];
      c[col * 4 + row] = s;
    }
  return c;
}

double determinant3(const Matrix& m) {
  return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) + m[8] * (m[1] * m[6] - m[5] * m[2]);
}

[[noreturn]] void fail(const Document& d, const std::string& message) { throw Error(std::string(d.kind) + " " + message); }

const json* member(const json& object, const char* key) {
  if (!object.is_object()) return nullptr;
  auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

const json& array(const Document& d, const char* key) {
  static const json empty = json::array();
  const json* a = member(d.root, key);
  if (!a) return empty;
  if (!a->is_array()) fail(d, std::string("'") + key + "' is not an array");
  return *a;
}

// A non-negative integer member, or `fallback` when absent.
uint64_t integer(const Document& d, const json& object, const char* key, const std::string& where, uint64_t fallback,
                 uint64_t max = 0xffffffffffffull) {
  const json* v = member(object, key);
  if (!v) return fallback;
  if (!v->is_number_integer() || (v->is_number_integer() && !v->is_number_unsigned() && v->get<int64_t>() < 0))
    fail(d, where + ": '" + key + "' is not a non-negative integer");
  uint64_t x = v->get<uint64_t>();
  if (x > max) fail(d, where + ": '" + key + "' " + count(x) + " is out of range (at most " + count(max) + ")");
  return x;
}

// An index into the top-level array `arrayName`.
size_t indexInto(const Document& d, const json& object, const char* key, const char* arrayName, const std::string& where) {
  const size_t n = array(d, arrayName).size();
  const json* v = member(object, key);
  if (!v) fail(d, where + ": '" + key + "' is missing");
  if (!v->is_number_integer() || (!v->is_number_unsigned() && v->get<int64_t>() < 0) || v->get<uint64_t>() >= n)
    fail(d, where + ": '" + key + "' is not a valid index into '" + arrayName + "' (" + count(n) + " entries)");
  return size_t(v->get<uint64_t>());
}

const json& entry(const Document& d, const char* arrayName, size_t i) {
  const json& e = array(d, arrayName)[i];
  if (!e.is_object()) fail(d, std::string(arrayName) + " " + count(i) + " is not an object");
  return e;
}

// ---- buffers ---------------------------------------------------------------------------------

bool decodeBase64(std::string_view in, std::string& out) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+' || c == '-') return 62;
    if (c == '/' || c == '_') return 63;
    return -1;
  };
  while (!in.empty() && in.back() == '=') in.remove_suffix(1);
  out.clear();
  out.reserve(in.size() / 4 * 3 + 3);
  uint32_t bits = 0;
  int have = 0;
  for (char c : in) {
    int v = value(c);
    if (v < 0) return false;
    bits = (bits << 6) | uint32_t(v);
    have += 6;
    if (have >= 8) {
      have -= 8;
      out.push_back(char((bits >> have) & 0xff));
    }
  }
  return true;
}

void loadBuffers(Document& d, std::string_view glbBinary, bool haveGlbBinary, const GltfResources& resources) {
  const json& buffers = array(d, "buffers");
  d.decoded.reserve(buffers.size());
  for (size_t i = 0; i < buffers.size(); ++i) {
    const std::string where = "buffer " + count(i);
    const json& b = entry(d, "buffers", i);
    const uint64_t length = integer(d, b, "byteLength", where, 0);
    if (!member(b, "byteLength")) fail(d, where + ": 'byteLength' is missing");
    std::string_view bytes;
    const json* uri = member(b, "uri");
    if (!uri) {
      if (i != 0 || !haveGlbBinary)
        fail(d, where + " has no 'uri'" + (d.kind == std::string("GLB") ? " and the file has no BIN chunk for it" : ""));
      bytes = glbBinary;
    } else {
      if (!uri->is_string()) fail(d, where + ": 'uri' is not a string");
      const std::string& u = uri->get_ref<const std::string&>();
      if (u.rfind("data:", 0) == 0) {
        size_t comma = u.find(',');
        if (comma == std::string::npos || u.substr(0, comma).find(";base64") == std::string::npos)
          fail(d, where + ": data URI is not base64");
        d.decoded.emplace_back();
        if (!decodeBase64(std::string_view(u).substr(comma + 1), d.decoded.back()))
          fail(d, where + ": data URI holds a character that is not base64");
        bytes = d.decoded.back();
      } else {
        auto it = std::find_if(resources.begin(), resources.end(), [&](const auto& r) { return r.first == u; });
        if (it == resources.end())
          fail(d, where + " refers to the file " + io::quoted(u) + ", which was not given (pass it beside the .gltf)");
        bytes = it->second;
      }
    }
    if (length > bytes.size())
      fail(d, where + ": byteLength " + count(length) + " but its data holds " + count(bytes.size()) + " bytes");
    d.buffers.push_back(bytes.substr(0, size_t(length)));
    d.totalBytes += length;
  }
}

// ---- accessors -------------------------------------------------------------------------------

size_t componentSize(uint64_t type) {
  switch (type) {
    case 5120: case 5121: return 1;
    case 5122: case 5123: return 2;
    case 5125: case 5126: return 4;
    default: return 0;
  }
}

double component(const char* p, uint64_t type, bool normalized) {
  switch (type) {
    case 5120: { double v = io::load<int8_t>(p); return normalized ? std::max(v / 127.0, -1.0) : v; }
    case 5121: { double v = io::load<uint8_t>(p); return normalized ? v / 255.0 : v; }
    case 5122: { double v = io::load<int16_t>(p); return normalized ? std::max(v / 32767.0, -1.0) : v; }
    case 5123: { double v = io::load<uint16_t>(p); return normalized ? v / 65535.0 : v; }
    case 5125: return io::load<uint32_t>(p);
    default: return io::load<float>(p);
  }
}

size_t componentsOf(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  if (type == "MAT2") return 4;
  if (type == "MAT3") return 9;
  if (type == "MAT4") return 16;
  return 0;
}

// A strided view of elements in a buffer view, bounds checked.
struct Strided {
  const char* data = nullptr;
  size_t stride = 0;
};

Strided viewFor(const Document& d, size_t viewIndex, uint64_t offset, uint64_t count_, size_t elementSize,
                const std::string& where) {
  const json& view = entry(d, "bufferViews", viewIndex);
  const std::string vw = "bufferView " + count(viewIndex);
  const size_t buffer = indexInto(d, view, "buffer", "buffers", vw);
  const uint64_t viewOffset = integer(d, view, "byteOffset", vw, 0);
  if (!member(view, "byteLength")) fail(d, vw + ": 'byteLength' is missing");
  const uint64_t viewLength = integer(d, view, "byteLength", vw, 0);
  const uint64_t stride = integer(d, view, "byteStride", vw, elementSize, 252);
  if (stride < elementSize)
    fail(d, vw + ": byteStride " + count(stride) + " is smaller than the " + count(elementSize) + "-byte elements of " + where);
  const uint64_t bufferLength = d.buffers[buffer].size();
  if (viewOffset > bufferLength || viewLength > bufferLength - viewOffset)
    fail(d, vw + ": bytes " + count(viewOffset) + ".." + count(viewOffset + viewLength) + " run past the end of buffer " +
                count(buffer) + " (" + count(bufferLength) + " bytes)");
  if (count_ > 0 && (offset > viewLength || (count_ - 1) * stride + elementSize > viewLength - offset))
    fail(d, where + ": " + count(count_) + " elements of " + count(elementSize) + " bytes (stride " + count(stride) +
                ") from byte " + count(offset) + " of bufferView " + count(viewIndex) + " run past its end (" +
                count(viewLength) + " bytes)");
  return {d.buffers[buffer].data() + viewOffset + offset, size_t(stride)};
}

namespace {

// Accessor `index` as T, `components` per element (normalized integers mapped to [-1, 1]); T is
// double, or uint32_t for an unsigned integer accessor that is not normalized (indices: read
// without a double per index in between).
template <class T>
std::vector<T> readAccessorAs(const Document& d, size_t index, size_t components, const std::string& role) {
  const json& a = entry(d, "accessors", index);
  const std::string where = "accessor " + count(index) + " (" + role + ")";
  const uint64_t type = integer(d, a, "componentType", where, 0);
  const size_t size = componentSize(type);
  if (size == 0) fail(d, where + ": unknown componentType " + std::to_string(type));
  const json* t = member(a, "type");
  if (!t || !t->is_string()) fail(d, where + ": 'type' is missing");
  if (componentsOf(t->get<std::string>()) != components)
    fail(d, where + ": type " + io::quoted(t->get<std::string>()) + ", expected " + (components == 1 ? "SCALAR" : "VEC3"));
  if (!member(a, "count")) fail(d, where + ": 'count' is missing");
  const uint64_t n = integer(d, a, "count", where, 0, 0xffffffffu);
  const json* normalizedMember = member(a, "normalized");
  const bool normalized = normalizedMember && normalizedMember->is_boolean() && normalizedMember->get<bool>();
  const size_t elementSize = size * components;
  std::vector<T> out;
  if (member(a, "bufferView")) {
    const size_t view = indexInto(d, a, "bufferView", "bufferViews", where);
    Strided s = viewFor(d, view, integer(d, a, "byteOffset", where, 0), n, elementSize, where);
    out.resize(size_t(n) * components);
    // The component type chosen once, not per value (float32 and uint32 are the common cases).
    auto each = [&](auto load) {
      for (size_t i = 0; i < n; ++i)
        for (size_t c = 0; c < components; ++c) out[i * components + c] = load(s.data + i * s.stride + c * size);
    };
    if (type == 5126) each([](const char* p) { return T(io::load<float>(p)); });
    else if (type == 5125) each([](const char* p) { return T(io::load<uint32_t>(p)); });
    else each([&](const char* p) { return T(component(p, type, normalized)); });
  } else {
    // All zeros (then sparse values): bounded by the bytes there are, so a count alone allocates nothing absurd.
    if (n > d.totalBytes + 1024)
      fail(d, where + ": " + count(n) + " elements without a bufferView, more than the file's " + count(d.totalBytes) + " bytes");
    out.assign(size_t(n) * components, T(0));
  }
  if (const json* sparse = member(a, "sparse")) {
    const std::string sw = where + " sparse";
    const uint64_t m = integer(d, *sparse, "count", sw, 0, n);
    const json* idx = member(*sparse, "indices");
    const json* val = member(*sparse, "values");
    if (!idx || !val) fail(d, sw + ": 'indices' or 'values' is missing");
    const uint64_t indexType = integer(d, *idx, "componentType", sw + " indices", 0);
    if (indexType != 5121 && indexType != 5123 && indexType != 5125) fail(d, sw + ": indices componentType must be unsigned");
    Strided si = viewFor(d, indexInto(d, *idx, "bufferView", "bufferViews", sw + " indices"),
                         integer(d, *idx, "byteOffset", sw, 0), m, componentSize(indexType), sw + " indices");
    Strided sv = viewFor(d, indexInto(d, *val, "bufferView", "bufferViews", sw + " values"),
                         integer(d, *val, "byteOffset", sw, 0), m, elementSize, sw + " values");
    for (size_t k = 0; k < m; ++k) {
      const double target = component(si.data + k * componentSize(indexType), indexType, false);
      if (target >= double(n)) fail(d, sw + ": index " + count(uint64_t(target)) + " is past the accessor's " + count(n) + " elements");
      for (size_t c = 0; c < components; ++c)
        out[size_t(target) * components + c] = T(component(sv.data + k * elementSize + c * size, type, normalized));
    }
  }
  return out;
}

}  // namespace

std::vector<double> readAccessor(const Document& d, size_t index, size_t components, const std::string& role) {
  return readAccessorAs<double>(d, index, components, role);
}

// An accessor whose values are unsigned integers as they are (componentType 5121, 5123 or 5125,
// not normalized): read as uint32_t, each value is what the double path would give. Looks only;
// readAccessorAs checks the rest and names what is wrong.
bool plainUnsignedIntegers(const Document& d, size_t index) {
  const json& a = array(d, "accessors")[index];
  const json* type = member(a, "componentType");
  const json* normalized = member(a, "normalized");
  if (!type || !type->is_number_unsigned()) return false;
  const uint64_t t = type->get<uint64_t>();
  return (t == 5121 || t == 5123 || t == 5125) && !(normalized && normalized->is_boolean() && normalized->get<bool>());
}

// ---- the scene -------------------------------------------------------------------------------

Matrix localMatrix(const Document& d, const json& node, const std::string& where) {
  auto numbers = [&](const char* key, size_t n, std::array<double, 16>& out) {
    const json* v = member(node, key);
    if (!v) return false;
    if (!v->is_array() || v->size() != n) fail(d, where + ": '" + key + "' must be an array of " + std::to_string(n) + " numbers");
    for (size_t i = 0; i < n; ++i) {
      if (!(*v)[i].is_number()) fail(d, where + ": '" + key + "' must be an array of " + std::to_string(n) + " numbers");
      out[i] = (*v)[i].get<double>();
      if (!std::isfinite(out[i])) fail(d, where + ": '" + key + "' has a value that is not finite");
    }
    return true;
  };
  Matrix m = kIdentity;
  if (numbers("matrix", 16, m)) return m;
  std::array<double, 16> t{}, r{0, 0, 0, 1}, s{1, 1, 1};
  numbers("translation", 3, t);
  numbers("rotation", 4, r);
  numbers("scale", 3, s);
  const double qx = r[0], qy = r[1], qz = r[2], qw = r[3];
  // T * R * S, column-major.
  const double rot[9] = {1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy + qz * qw),     2 * (qx * qz - qy * qw),
                         2 * (qx * qy - qz * qw),     1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + qx * qw),
                         2 * (qx * qz + qy * qw),     2 * (qy * qz - qx * qw),     1 - 2 * (qx * qx + qy * qy)};
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row) m[col * 4 + row] = rot[col * 3 + row] * s[col];
  m[12] = t[0], m[13] = t[1], m[14] = t[2];
  return m;
}

struct Instance {
  size_t mesh;
  Matrix world;
};

// Meshes of the default scene (or scene 0; or every mesh when there is no scene) with their world matrices.
std::vector<Instance> sceneInstances(const Document& d) {
  std::vector<Instance> out;
  const json& scenes = array(d, "scenes");
  const json& nodes = array(d, "nodes");
  if (scenes.empty()) {
    for (size_t i = 0; i < array(d, "meshes").size(); ++i) out.push_back({i, kIdentity});
    return out;
  }
  const size_t scene = member(d.root, "scene") ? indexInto(d, d.root, "scene", "scenes", "the document") : 0;
  const json& roots = *[&] {
    const json& s = entry(d, "scenes", scene);
    const json* n = member(s, "nodes");
    static const json none = json::array();
    if (n && !n->is_array()) fail(d, "scene " + count(scene) + ": 'nodes' is not an array");
    return n ? n : &none;
  }();
  std::vector<char> seen(nodes.size(), 0);
  std::vector<std::pair<size_t, Matrix>> stack;
  auto push = [&](const json& index, const Matrix& parent, const std::string& where) {
    if (!index.is_number_unsigned() || index.get<uint64_t>() >= nodes.size())
      fail(d, where + " lists a node index that is not valid (" + count(nodes.size()) + " nodes)");
    const size_t n = size_t(index.get<uint64_t>());
    if (seen[n]) fail(d, "node " + count(n) + " appears twice in the scene (the node hierarchy must be a tree)");
    seen[n] = 1;
    stack.push_back({n, parent});
  };
  for (size_t i = roots.size(); i-- > 0;) push(roots[i], kIdentity, "scene " + count(scene));
  while (!stack.empty()) {
    auto [n, parent] = stack.back();
    stack.pop_back();
    const std::string where = "node " + count(n);
    const json& node = entry(d, "nodes", n);
    const Matrix world = multiply(parent, localMatrix(d, node, where));
    if (member(node, "mesh")) out.push_back({indexInto(d, node, "mesh", "meshes", where), world});
    if (const json* children = member(node, "children")) {
      if (!children->is_array()) fail(d, where + ": 'children' is not an array");
      for (size_t i = children->size(); i-- > 0;) push((*children)[i], world, where);
    }
  }
  return out;
}

// Extensions a file may require that leave its geometry as mrvol reads it: quantized positions (read),
// and materials, textures, lights, cameras, animation (not read at all).
bool geometryUnaffected(const std::string& name) {
  static const char* const prefixes[] = {"KHR_materials_", "KHR_texture_", "EXT_texture_", "KHR_lights_", "EXT_lights_",
                                         "KHR_animation_", "KHR_xmp", "KHR_mesh_quantization", "EXT_materials_"};
  for (const char* prefix : prefixes)
    if (name.rfind(prefix, 0) == 0) return true;
  return false;
}

// A required extension mrvol cannot honour is refused (the spec: a loader must not read the file
// without it), naming it.
void checkExtensions(const Document& d) {
  const json* required = member(d.root, "extensionsRequired");
  if (!required || !required->is_array()) return;
  for (const json& e : *required) {
    if (!e.is_string()) continue;
    const std::string& name = e.get_ref<const std::string&>();
    if (name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression" || name == "EXT_mesh_gpu_instancing" ||
        name == "KHR_meshopt_compression")
      fail(d, "file requires the extension " + name + ", which mrvol does not decode (export the model without it)");
    if (!geometryUnaffected(name))
      fail(d, "file requires the extension " + io::quoted(name) + ", which mrvol does not know (export the model without it)");
  }
}

const char* modeName(uint64_t mode) {
  switch (mode) {
    case 0: return "POINTS";
    case 1: return "LINES";
    case 2: return "LINE_LOOP";
    case 3: return "LINE_STRIP";
    default: return "unknown";
  }
}

SceneGeometry collectScene(const Document& d) {
  checkExtensions(d);
  const json* asset = member(d.root, "asset");
  if (!asset || !asset->is_object()) fail(d, "JSON has no 'asset' object: this is not a glTF file");
  const json* version = member(*asset, "version");
  if (!version || !version->is_string() || version->get<std::string>().rfind("2.", 0) != 0)
    fail(d, "asset version is not 2.x: mrvol reads glTF 2.0");
  SceneGeometry out;
  TriangleMesh& m = out.mesh;
  const uint64_t maxTriangles = std::max<uint64_t>(d.totalBytes * 16, uint64_t(1) << 20);
  uint64_t sourceBase = 0;  // running index over the primitives' POSITION accessors
  uint64_t skippedModes[4] = {0, 0, 0, 0};  // primitives of points and lines, left out
  std::vector<uint32_t>& sourceOfOutput = out.sourceOfVertex;
  for (const Instance& instance : sceneInstances(d)) {
    const json& mesh = entry(d, "meshes", instance.mesh);
    const json* primitives = member(mesh, "primitives");
    if (!primitives || !primitives->is_array()) fail(d, "mesh " + count(instance.mesh) + ": 'primitives' is missing");
    const bool flip = determinant3(instance.world) < 0;
    if (determinant3(instance.world) == 0) fail(d, "mesh " + count(instance.mesh) + ": its node transform is singular");
    for (size_t p = 0; p < primitives->size(); ++p) {
      const std::string where = "mesh " + count(instance.mesh) + " primitive " + count(p);
      const json& primitive = (*primitives)[p];
      const uint64_t mode = integer(d, primitive, "mode", where, 4);
      if (mode > 6) fail(d, where + ": unknown mode " + std::to_string(mode));
      // Lines and points (a model's edges or markers beside its surface) are not surface: left out,
      // as an OBJ's l and p lines are.
      if (mode <= 3) {
        skippedModes[mode]++;
        continue;
      }
      const json* attributes = member(primitive, "attributes");
      if (!attributes || !member(*attributes, "POSITION")) fail(d, where + " has no POSITION attribute");
      const size_t positionAccessor = indexInto(d, *attributes, "POSITION", "accessors", where + " attributes");
      // Draco data beside uncompressed accessors (the extension used, not required): those are read.
      if (const json* ext = member(primitive, "extensions"))
        if (member(*ext, "KHR_draco_mesh_compression") && !member(entry(d, "accessors", positionAccessor), "bufferView"))
          fail(d, where + " is Draco-compressed, which mrvol does not decode (export the model without compression)");
      // float32 positions (the common case) read as floats: exact, and half the bytes of doubles.
      // (A componentType that is not a valid number is named by readAccessor.)
      const json* positionType = member(entry(d, "accessors", positionAccessor), "componentType");
      const bool floatPositions =
          positionType && positionType->is_number_unsigned() && positionType->get<uint64_t>() == 5126;
      std::vector<float> localFloat;
      std::vector<double> localDouble;
      if (floatPositions) localFloat = readAccessorAs<float>(d, positionAccessor, 3, "POSITION of " + where);
      else localDouble = readAccessor(d, positionAccessor, 3, "POSITION of " + where);
      const size_t vertexCount = (floatPositions ? localFloat.size() : localDouble.size()) / 3;
      std::vector<uint32_t> indices;
      if (member(primitive, "indices")) {
        const size_t ia = indexInto(d, primitive, "indices", "accessors", where);
        const std::string role = "indices of " + where;
        auto outOfRange = [&](size_t i, uint64_t value) {
          fail(d, where + ": index " + count(i) + " is " + count(value) + " but POSITION has " + count(vertexCount) + " vertices");
        };
        if (plainUnsignedIntegers(d, ia)) {
          indices = readAccessorAs<uint32_t>(d, ia, 1, role);
          for (size_t i = 0; i < indices.size(); ++i)
            if (indices[i] >= vertexCount) outOfRange(i, indices[i]);
        } else {
          const std::vector<double> raw = readAccessor(d, ia, 1, role);
          // glTF indices are unsigned integers; a signed or float accessor could hold -3 or 1.5.
          const uint64_t indexType = integer(d, entry(d, "accessors", ia), "componentType", where, 0);
          if (indexType != 5121 && indexType != 5123 && indexType != 5125)
            fail(d, "accessor " + count(ia) + " (indices of " + where + "): componentType " + std::to_string(indexType) +
                        ", indices must be unsigned integers (5121, 5123 or 5125)");
          indices.resize(raw.size());
          for (size_t i = 0; i < raw.size(); ++i) {
            if (raw[i] >= double(vertexCount)) outOfRange(i, uint64_t(raw[i]));
            indices[i] = uint32_t(raw[i]);
          }
        }
      } else {
        indices.resize(vertexCount);
        for (size_t i = 0; i < vertexCount; ++i) indices[i] = uint32_t(i);
      }
      // Triangles as local vertex triples.
      std::vector<uint32_t> triangles;
      if (mode == 4) {
        if (indices.size() % 3 != 0)
          fail(d, where + ": " + count(indices.size()) + " " + (member(primitive, "indices") ? "indices" : "vertices") +
                      " is not a multiple of 3 (mode TRIANGLES)");
        triangles = std::move(indices);
      } else {
        for (size_t i = 0; i + 2 < indices.size(); ++i) {
          uint32_t a, b, c;
          if (mode == 5) a = indices[i], b = indices[i + 1 + (i % 2)], c = indices[i + 2 - (i % 2)];
          else a = indices[i + 1], b = indices[i + 2], c = indices[0];
          if (a == b || b == c || a == c) continue;  // strips join runs with degenerate triangles
          triangles.insert(triangles.end(), {a, b, c});
        }
      }
      out.sourceFaces += triangles.size() / 3;
      if (m.faceCount() + triangles.size() / 3 > maxTriangles)
        fail(d, "scene: more than " + count(maxTriangles) + " triangles from a " + count(d.totalBytes) +
                    "-byte file (nodes instance the meshes too often)");
      // The vertices the triangles use, in accessor order, transformed.
      std::vector<uint32_t> outputOf(vertexCount, UINT32_MAX);
      for (uint32_t v : triangles) outputOf[v] = 0;
      // Room for every vertex of the primitive, written in place, then cut back to those used.
      const size_t firstVertex = m.vertexCount();
      m.positions.resize(3 * (firstVertex + vertexCount));
      sourceOfOutput.resize(firstVertex + vertexCount);
      double* position = m.positions.data() + 3 * firstVertex;
      uint32_t* source = sourceOfOutput.data() + firstVertex;
      size_t used = 0;
      const Matrix& w = instance.world;
      auto place = [&](const auto* local) {
        for (size_t v = 0; v < vertexCount; ++v) {
          if (outputOf[v] == UINT32_MAX) continue;
          outputOf[v] = uint32_t(firstVertex + used);
          const double x = local[3 * v], y = local[3 * v + 1], z = local[3 * v + 2];
          for (int k = 0; k < 3; ++k) {
            const double value = w[k] * x + w[4 + k] * y + w[8 + k] * z + w[12 + k];
            if (!io::coordinateOk(value))
              fail(d, where + ": vertex " + count(v) + " coordinate " + io::coordinateProblem(value) +
                          " after the node transform");
            position[3 * used + k] = value;
          }
          source[used++] = uint32_t(std::min<uint64_t>(sourceBase + v, UINT32_MAX));
        }
      };
      if (floatPositions) place(localFloat.data());
      else place(localDouble.data());
      m.positions.resize(3 * (firstVertex + used));
      sourceOfOutput.resize(firstVertex + used);
      const size_t firstIndex = m.faces.size();
      const int second = flip ? 2 : 1;  // a mirroring transform turns the winding around
      if (firstVertex == 0 && used == vertexCount && !flip) {
        // Every vertex used, the first primitive: outputOf[v] == v, the triangles are the faces.
        m.faces.insert(m.faces.end(), triangles.begin(), triangles.end());
      } else {
        m.faces.resize(firstIndex + triangles.size());
        uint32_t* face = m.faces.data() + firstIndex;
        for (size_t t = 0; t < triangles.size(); t += 3) {
          face[t] = outputOf[triangles[t]];
          face[t + second] = outputOf[triangles[t + 1]];
          face[t + 3 - second] = outputOf[triangles[t + 2]];
        }
      }
      sourceBase += vertexCount;
      PrimitiveUse use;
      use.mesh = instance.mesh, use.primitive = p, use.positionAccessor = positionAccessor, use.world = instance.world;
      if (member(*attributes, "NORMAL")) use.normalAccessor = long(indexInto(d, *attributes, "NORMAL", "accessors", where));
      use.outputOf = std::move(outputOf);
      use.triangles = std::move(triangles);
      out.uses.push_back(std::move(use));
    }
  }
  if (m.faces.empty()) {
    std::string others;
    for (uint64_t mode = 0; mode <= 3; ++mode)
      if (skippedModes[mode]) others += (others.empty() ? "" : ", ") + count(skippedModes[mode]) + " of mode " + modeName(mode);
    fail(d, others.empty() ? "scene has no triangles (no mesh, or only empty primitives)"
                           : "scene has no triangles, only primitives of lines or points (" + others + "): mrvol reads surfaces");
  }
  return out;
}

namespace {

ImportedMesh readDocument(const Document& d) {
  SceneGeometry scene = collectScene(d);
  ImportedMesh out;
  out.mesh = std::move(scene.mesh);
  out.sourceFaces = scene.sourceFaces;
  out.sourceVertices = out.mesh.vertexCount();
  std::vector<uint32_t> first;
  out.welded = weldExactPositions(out.mesh, &first);
  if (out.welded == 0) {  // first[i] == i
    out.sourceVertex = std::move(scene.sourceOfVertex);
  } else {
    out.sourceVertex.resize(first.size());
    for (size_t i = 0; i < first.size(); ++i) out.sourceVertex[i] = scene.sourceOfVertex[first[i]];
  }
  return out;
}

}  // namespace

void parseJson(Document& d, std::string_view text, uint64_t base) {
  try {
    d.root = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    // e.byte counts from 1 within the JSON text.
    std::string what = e.what();
    size_t colon = what.find("syntax error");
    fail(d, "JSON: syntax error at byte " + count(base + (e.byte > 0 ? e.byte - 1 : 0)) +
                (colon != std::string::npos ? " (" + what.substr(colon) + ")" : ""));
  } catch (const json::exception& e) {  // a number out of range (1e526), ...
    fail(d, std::string("JSON: ") + e.what());
  }
  if (!d.root.is_object()) fail(d, "JSON: the document is not an object");
}

Document openGltf(std::string_view text, const GltfResources& resources) {
  if (text.empty()) throw Error("empty glTF file (0 bytes)");
  Document d;
  d.totalBytes = text.size();
  if (text.substr(0, 4) == "glTF") throw Error("this is a GLB (binary glTF) file, not .gltf JSON: read it as GLB");
  parseJson(d, text, 0);
  loadBuffers(d, {}, false, resources);
  return d;
}

Document openGlb(std::string_view b, const GltfResources& resources) {
  if (b.empty()) throw Error("empty GLB file (0 bytes)");
  if (b.size() < 12 || b.substr(0, 4) != "glTF")
    throw Error("not a GLB file: it does not start with the magic 'glTF'" + io::looksLike(b));
  const uint32_t version = io::load<uint32_t>(b.data() + 4);
  const uint32_t length = io::load<uint32_t>(b.data() + 8);
  if (version != 2) throw Error("GLB header: version " + std::to_string(version) + ", mrvol reads glTF 2.0");
  if (length > b.size())
    throw Error("GLB header: length " + count(length) + " runs past the end (file is " + count(b.size()) + " bytes)");
  if (length < 12) throw Error("GLB header: length " + count(length) + " is shorter than the 12-byte header");
  std::string_view file = b.substr(0, length);
  std::string_view jsonChunk, binChunk;
  bool haveJson = false, haveBin = false;
  size_t pos = 12;
  for (size_t chunk = 0; pos < file.size(); ++chunk) {
    if (file.size() - pos < 8)
      throw Error("GLB chunk " + std::to_string(chunk) + " header at byte " + count(pos) + " runs past the end (file is " +
                  count(file.size()) + " bytes)");
    const uint32_t chunkLength = io::load<uint32_t>(file.data() + pos);
    const uint32_t type = io::load<uint32_t>(file.data() + pos + 4);
    if (chunkLength > file.size() - pos - 8)
      throw Error("GLB chunk " + std::to_string(chunk) + " length " + count(chunkLength) + " runs past the end (file is " +
                  count(file.size()) + " bytes)");
    std::string_view data = file.substr(pos + 8, chunkLength);
    if (chunk == 0) {
      if (type != 0x4E4F534A) throw Error("GLB chunk 0 is not JSON (type " + std::to_string(type) + ")");
      jsonChunk = data, haveJson = true;
    } else if (type == 0x004E4942 && !haveBin) {
      binChunk = data, haveBin = true;
    }
    pos += 8 + size_t(chunkLength);
  }
  if (!haveJson) throw Error("GLB: the file has no JSON chunk");
  Document d;
  d.kind = "GLB";
  d.totalBytes = b.size();
  parseJson(d, jsonChunk, 20);
  loadBuffers(d, binChunk, haveBin, resources);
  return d;
}

}  // namespace gltf

namespace {

// The reader checks the types it reads; a JSON exception left over is still the file's fault.
template <class F>
ImportedMesh withJsonErrors(const char* kind, F&& read) {
  try {
    return read();
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string(kind) + " JSON: " + e.what());
  }
}

}  // namespace

ImportedMesh readGltf(std::string_view text, const GltfResources& resources) {
  ImportedMesh out = withJsonErrors("glTF", [&] { return gltf::readDocument(gltf::openGltf(text, resources)); });
  out.format = MeshFormat::Gltf;
  out.variant = "glTF";
  return out;
}

ImportedMesh readGlb(std::string_view bytes, const GltfResources& resources) {
  ImportedMesh out = withJsonErrors("GLB", [&] { return gltf::readDocument(gltf::openGlb(bytes, resources)); });
  out.format = MeshFormat::Glb;
  out.variant = "GLB";
  return out;
}

}  // namespace mrvol
