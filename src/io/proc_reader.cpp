// The .proc reader of the collision code (the original's LoadProcBSP and
// ParseProcNodes, rewritten from the original's behaviour and the .proc
// layout): the header, sections skipped as braced blocks until `nodes`, then
// the node count and per node ( a b c d ) front back.
//
// The reader throws detail::SyntaxError internally; parseProcText catches it.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include "cmkit/proc_file.h"
#include "text/lexer.h"

namespace cmkit {

namespace {

using detail::Lexer;
using detail::Token;
using detail::TokenKind;

/// The header the original expects (compared ignoring case).
constexpr std::string_view kProcFileId = "mapProcFile003";

bool sameIgnoringCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto fold = [](char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; };
    if (fold(a[i]) != fold(b[i])) return false;
  }
  return true;
}

std::string shown(const Token& t) {
  if (t.kind == TokenKind::End) return "the end of the file";
  if (t.kind == TokenKind::String) return "\"" + std::string(t.text) + "\"";
  return "'" + std::string(t.text) + "'";
}

class ProcReader {
 public:
  explicit ProcReader(std::string_view text) : lex_(text) {}

  /// The nodes of the file; `badHeader` is set (and nothing read) when the
  /// first token is not the .proc id.
  std::vector<ProcNode> read(std::string& badHeader) {
    const Token id = lex_.next();
    if (id.kind == TokenKind::End || !sameIgnoringCase(id.text, kProcFileId)) {
      badHeader = id.kind == TokenKind::End ? std::string() : std::string(id.text);
      return {};
    }
    for (;;) {
      const Token t = lex_.next();
      if (t.kind == TokenKind::End) return {};  // no nodes section: nothing to prune with
      if (t.kind == TokenKind::Name &&
          (t.text == "model" || t.text == "shadowModel" || t.text == "interAreaPortals")) {
        skipBracedSection(t);
        continue;
      }
      if (t.is(TokenKind::Name, "nodes")) return nodes();
      Lexer::fail(t,
                  "unexpected " + shown(t) +
                      " in a .proc file: expected a section (model, shadowModel, interAreaPortals or nodes)");
    }
  }

 private:
  void expect(char c, std::string_view where) {
    const Token t = lex_.next();
    if (!t.isPunct(c))
      Lexer::fail(t, "expected '" + std::string(1, c) + "' " + std::string(where) + ", found " + shown(t));
  }

  void skipBracedSection(const Token& section) {
    expect('{', "after " + shown(section));
    int depth = 1;
    while (depth > 0) {
      const Token t = lex_.next();
      if (t.kind == TokenKind::End)
        Lexer::fail(section,
                    "the section " + shown(section) + " has no closing '}' before the end of the file");
      if (t.isPunct('{')) ++depth;
      if (t.isPunct('}')) --depth;
    }
  }

  /// A number with an optional '-' token before it.
  float number(std::string_view what) {
    Token t = lex_.next();
    const bool negative = t.isPunct('-');
    if (negative) t = lex_.next();
    if (t.kind != TokenKind::Number) Lexer::fail(t, "expected " + std::string(what) + ", found " + shown(t));
    const float v = *detail::originalNumberValue(t.text);  // the lexer checked the form
    return negative ? -v : v;
  }

  /// An integer in [lo, hi] (an optional '-' token before it).
  std::int32_t integer(std::string_view what, std::int64_t lo, std::int64_t hi, Token* where = nullptr) {
    Token t = lex_.next();
    const Token first = t;
    const bool negative = t.isPunct('-');
    if (negative) t = lex_.next();
    if (where) *where = first;
    if (t.kind != TokenKind::Number || t.text.find_first_not_of("0123456789") != std::string_view::npos)
      Lexer::fail(t, "expected " + std::string(what) + " (an integer), found " + shown(t));
    std::int64_t v = 0;
    for (const char c : t.text) {
      v = v * 10 + (c - '0');
      if (v > hi - lo + 1) break;  // out of range either way
    }
    if (negative) v = -v;
    if (v < lo || v > hi)
      Lexer::fail(first, std::string(what) + " " + (negative ? "-" : "") + std::string(t.text) +
                             " is out of range (" + std::to_string(lo) + ".." + std::to_string(hi) + ")");
    return static_cast<std::int32_t>(v);
  }

  std::vector<ProcNode> nodes() {
    expect('{', "after 'nodes'");
    const std::int32_t count = integer("the number of nodes", 0, INT32_MAX);
    std::vector<ProcNode> out;
    out.reserve(std::min<std::size_t>(std::size_t(count), 1u << 16));
    for (std::int32_t i = 0; i < count; ++i) {
      const std::string node = "node " + std::to_string(i);
      expect('(', "to start the plane of " + node);
      float p[4];
      for (float& v : p) v = number("a number of the plane of " + node);
      expect(')', "to end the plane of " + node + " (four numbers: a b c d)");
      ProcNode n;
      n.plane = Plane(Vec3(p[0], p[1], p[2]), -p[3]);
      for (int side = 0; side < 2; ++side) {
        Token at;
        const char* which = side == 0 ? "the front child of " : "the back child of ";
        n.children[side] = integer(which + node, INT32_MIN + 1, INT32_MAX, &at);
        // A node child must be a later node (as a compiler numbers them):
        // within the tree, and the walk down always ends.
        if (n.children[side] > 0 && (n.children[side] <= i || n.children[side] >= count))
          Lexer::fail(at, which + node + " is node " + std::to_string(n.children[side]) +
                              ": expected a node after " + std::to_string(i) + " and below the node count " +
                              std::to_string(count) + " (0 = solid, negative = area)");
      }
      out.push_back(n);
    }
    expect('}', "to end the nodes section (after " + std::to_string(count) + " nodes)");
    return out;
  }

  Lexer lex_;
};

}  // namespace

Result<ProcBsp> parseProcText(std::string_view text, std::string fileName,
                              std::vector<std::string>* warnings) {
  ProcBsp bsp;
  bsp.fileName = std::move(fileName);
  std::string badHeader;
  try {
    bsp.nodes = ProcReader(text).read(badHeader);
  } catch (const detail::SyntaxError& e) {
    return detail::toError(e, bsp.fileName);
  }
  if (bsp.nodes.empty() && warnings && !badHeader.empty()) {
    warnings->push_back(bsp.fileName + ": bad id '" + badHeader + "' instead of '" +
                        std::string(kProcFileId) + "'; the .proc is not used");
  } else if (bsp.nodes.empty() && warnings && text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
    warnings->push_back(bsp.fileName + ": empty file; the .proc is not used");
  }
  return bsp;
}

Result<ProcBsp> loadProcFile(const std::string& path, std::vector<std::string>* warnings) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error("cannot open the .proc file", path);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) return Error("cannot read the .proc file", path);
  return parseProcText(ss.str(), path, warnings);
}

std::string procPathForMap(const std::string& mapPath) {
  return std::filesystem::path(mapPath).replace_extension(".proc").string();
}

Result<std::optional<ProcBsp>> loadProcFileForMap(const std::string& mapPath,
                                                  std::vector<std::string>* warnings) {
  const std::string path = procPathForMap(mapPath);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::optional<ProcBsp>();
  Result<ProcBsp> bsp = loadProcFile(path, warnings);
  if (!bsp) return bsp.error();
  return std::optional<ProcBsp>(std::move(*bsp));
}

}  // namespace cmkit
