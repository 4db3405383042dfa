// The mesh file checks before assimp (mesh_checks.h).
#include "mesh_checks.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace cmkit {

namespace {

/// A scalar type of the PLY format: its name and size in bytes.
struct PlyType {
  std::string_view name;
  int bytes;
  bool isSigned;
};

constexpr std::array<PlyType, 16> kTypes = {{{"char", 1, true},
                                             {"uchar", 1, false},
                                             {"short", 2, true},
                                             {"ushort", 2, false},
                                             {"int", 4, true},
                                             {"uint", 4, false},
                                             {"float", 4, true},
                                             {"double", 8, true},
                                             {"int8", 1, true},
                                             {"uint8", 1, false},
                                             {"int16", 2, true},
                                             {"uint16", 2, false},
                                             {"int32", 4, true},
                                             {"uint32", 4, false},
                                             {"float32", 4, true},
                                             {"float64", 8, true}}};

const PlyType* findType(std::string_view name) {
  for (const PlyType& t : kTypes)
    if (t.name == name) return &t;
  return nullptr;
}

struct PlyProperty {
  const PlyType* count = nullptr;  ///< a list's count type; null for a scalar
  const PlyType* value = nullptr;
};

struct PlyElement {
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

/// Splits off the next line of `text` (without its \n or \r\n).
std::string_view nextLine(std::string_view& text) {
  const std::size_t end = text.find('\n');
  std::string_view line = text.substr(0, end);
  text = end == std::string_view::npos ? std::string_view{} : text.substr(end + 1);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

/// The blank-separated words of a line.
std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

/// A decimal count, false when it is not one or overflows.
bool parseCount(std::string_view text, std::uint64_t& out) {
  if (text.empty() || text.size() > 19) return false;
  out = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return false;
    out = out * 10 + std::uint64_t(c - '0');
  }
  return true;
}

/// An unsigned or signed integer of `type` at `p`; false when negative.
bool readListCount(const unsigned char* p, const PlyType& type, bool bigEndian, std::uint64_t& out) {
  std::uint64_t v = 0;
  for (int k = 0; k < type.bytes; ++k) {
    const int byte = bigEndian ? k : type.bytes - 1 - k;
    v = (v << 8) | p[byte];
  }
  if (type.isSigned && (v >> (8 * type.bytes - 1)) != 0) return false;
  out = v;
  return true;
}

/// Where binary data of `elements` ends too soon, or empty.
std::string binaryDataProblem(std::string_view data, const std::vector<PlyElement>& elements,
                              bool bigEndian) {
  const auto* p = reinterpret_cast<const unsigned char*>(data.data());
  std::uint64_t left = data.size();
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const PlyElement& element = elements[e];
    if (element.properties.empty()) continue;
    // Every row takes a byte at least: more rows than bytes cannot fit.
    if (element.count > left)
      return "the PLY file's binary data ends before element " + std::to_string(e + 1);
    for (std::uint64_t row = 0; row < element.count; ++row) {
      for (const PlyProperty& property : element.properties) {
        std::uint64_t bytes = std::uint64_t(property.value->bytes);
        if (property.count) {
          std::uint64_t n = 0;
          if (left < std::uint64_t(property.count->bytes))
            return "the PLY file's binary data ends in element " + std::to_string(e + 1);
          if (!readListCount(p, *property.count, bigEndian, n))
            return "the PLY file has a negative list length in element " + std::to_string(e + 1);
          p += property.count->bytes;
          left -= std::uint64_t(property.count->bytes);
          if (n > left / bytes) return "the PLY file's binary data ends in element " + std::to_string(e + 1);
          bytes *= n;
        }
        if (bytes > left) return "the PLY file's binary data ends in element " + std::to_string(e + 1);
        p += bytes;
        left -= bytes;
      }
    }
  }
  return {};
}

}  // namespace

std::string plyProblem(std::string_view file) {
  std::string_view rest = file;
  if (nextLine(rest) != "ply") return "the PLY file does not start with the line \"ply\"";
  enum class Format { None, Ascii, Little, Big } format = Format::None;
  std::vector<PlyElement> elements;
  for (int lineNumber = 2; !rest.empty(); ++lineNumber) {
    const std::vector<std::string_view> w = words(nextLine(rest));
    const std::string at = "PLY header line " + std::to_string(lineNumber) + ": ";
    if (w.empty()) continue;
    const std::string_view key = w[0];
    if (key == "end_header") {
      if (format == Format::None) return "the PLY header has no format line";
      if (format == Format::Ascii) return {};
      return binaryDataProblem(rest, elements, format == Format::Big);
    }
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      if (w.size() != 3 || w[2] != "1.0")
        return at + "expected \"format ascii|binary_little_endian|binary_big_endian 1.0\"";
      if (w[1] == "ascii") {
        format = Format::Ascii;
      } else if (w[1] == "binary_little_endian") {
        format = Format::Little;
      } else if (w[1] == "binary_big_endian") {
        format = Format::Big;
      } else {
        return at + "expected \"format ascii|binary_little_endian|binary_big_endian 1.0\"";
      }
    } else if (key == "element") {
      PlyElement element;
      if (w.size() != 3 || !parseCount(w[2], element.count)) return at + "expected \"element NAME COUNT\"";
      elements.push_back(element);
    } else if (key == "property") {
      if (elements.empty()) return at + "a property before any element";
      PlyProperty property;
      if (w.size() == 3) {
        property.value = findType(w[1]);
      } else if (w.size() == 5 && w[1] == "list") {
        property.count = findType(w[2]);
        property.value = findType(w[3]);
        if (property.count && property.count->name.find("float") != std::string_view::npos)
          property.count = nullptr;
        if (property.count && property.count->name == "double") property.count = nullptr;
        if (!property.count) property.value = nullptr;
      }
      if (!property.value) return at + "expected \"property TYPE NAME\" or \"property list TYPE TYPE NAME\"";
      elements.back().properties.push_back(property);
    } else {
      return at + "unknown keyword \"" + std::string(key.substr(0, 32)) + "\"";
    }
  }
  return "the PLY header has no end_header line";
}

namespace {

/// A little-endian 32-bit number at byte `at` of `file` (in range).
std::uint32_t readU32(std::string_view file, std::size_t at) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(file[at + std::size_t(k)]);
  return v;
}

}  // namespace

std::string glbProblem(std::string_view file) {
  // Header: magic "glTF", version, total length; then chunks of a length,
  // a type and the data (4-byte aligned by the format; not required here).
  constexpr std::size_t kHeaderBytes = 12, kChunkHeaderBytes = 8;
  if (file.substr(0, 4) != "glTF") return {};
  if (file.size() < kHeaderBytes) return "the GLB file's header is cut off";
  const std::uint64_t total = readU32(file, 8);
  if (total > file.size())
    return "the GLB header says the file is " + std::to_string(total) + " bytes long; it has " +
           std::to_string(file.size());
  std::size_t at = kHeaderBytes;
  for (int chunk = 1; at < total; ++chunk) {
    if (total - at < kChunkHeaderBytes)
      return "the GLB file's chunk " + std::to_string(chunk) + " header is cut off";
    const std::uint64_t length = readU32(file, at);
    if (length > total - at - kChunkHeaderBytes)
      return "the GLB file's chunk " + std::to_string(chunk) + " is " + std::to_string(length) +
             " bytes long; the file has " + std::to_string(total - at - kChunkHeaderBytes) +
             " after its header";
    at += kChunkHeaderBytes + std::size_t(length);
  }
  return {};
}

}  // namespace cmkit
