// Reading query lines and their result lines back for drawing
// (docs/query-format.md). Tolerant: a line that cannot be read gives a
// record with an error, never an exception or an abort.
#include <cstdlib>
#include <string>
#include <unordered_map>

#include "cmkit/tools/debug_draw.h"

namespace cmkit {
namespace {

using Fields = std::unordered_map<std::string, std::string>;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> splitLines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t nl = text.find('\n', pos);
    if (nl == std::string_view::npos) nl = text.size();
    const std::string_view line = trim(text.substr(pos, nl - pos));
    if (!line.empty() && line.front() != '#') lines.push_back(line);
    pos = nl + 1;
  }
  return lines;
}

// The first word of a line, and its key=value pairs.
std::string_view splitFields(std::string_view line, Fields& out) {
  std::string_view first;
  std::size_t pos = 0;
  bool isFirst = true;
  while (pos < line.size()) {
    while (pos < line.size() && (line[pos] == ' ' || line[pos] == '\t')) ++pos;
    std::size_t end = pos;
    while (end < line.size() && line[end] != ' ' && line[end] != '\t') ++end;
    const std::string_view tok = line.substr(pos, end - pos);
    if (!tok.empty()) {
      const std::size_t eq = tok.find('=');
      if (eq == std::string_view::npos) {
        if (isFirst) first = tok;
      } else {
        out[std::string(tok.substr(0, eq))] = std::string(tok.substr(eq + 1));
      }
      isFirst = false;
    }
    pos = end;
  }
  return first;
}

/// True for a query line (it starts with an operation name, not key=value).
bool looksLikeQuery(std::string_view line) {
  const std::size_t sp = line.find_first_of(" \t");
  return line.substr(0, sp).find('=') == std::string_view::npos;
}

bool parseReals(const Fields& f, const std::string& key, Real* out, int count) {
  const auto it = f.find(key);
  if (it == f.end()) return false;
  const char* p = it->second.c_str();
  for (int i = 0; i < count; ++i) {
    char* end = nullptr;
    out[i] = std::strtof(p, &end);
    if (end == p) return false;
    p = end;
    if (i + 1 < count) {
      if (*p != ',') return false;
      ++p;
    }
  }
  return *p == '\0';
}

bool parseVec(const Fields& f, const std::string& key, Vec3& out) {
  Real v[3];
  if (!parseReals(f, key, v, 3)) return false;
  out = {v[0], v[1], v[2]};
  return true;
}

bool parseMat(const Fields& f, const std::string& key, Mat3& out) {
  Real v[9];
  if (!parseReals(f, key, v, 9)) return false;
  out = Mat3{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}};
  return true;
}

template <typename Int>
void parseInt(const Fields& f, const std::string& key, Int& out) {
  const auto it = f.find(key);
  if (it != f.end()) out = Int(std::strtoll(it->second.c_str(), nullptr, 10));
}

ContactType contactTypeFromName(std::string_view name) {
  if (name == "edge") return ContactType::Edge;
  if (name == "modelvertex") return ContactType::ModelVertex;
  if (name == "trmvertex") return ContactType::TrmVertex;
  return ContactType::None;
}

void readQuery(std::string_view line, TraceRecord& r) {
  Fields f;
  r.op = std::string(splitFields(line, f));
  if (r.op == "pointcontents") {
    parseVec(f, "pos", r.start);
    r.end = r.start;
    return;
  }
  if (auto it = f.find("trm"); it != f.end()) {
    auto trm = TraceModel::parse(it->second);
    if (trm) {
      r.trm = std::move(*trm);
    } else {
      r.error = "bad trm: " + trm.error().message;
    }
  }
  parseMat(f, "trmaxis", r.trmAxis);
  if (!parseVec(f, "start", r.start)) r.error = "query has no start";
  r.end = r.start;
  if (r.op == "translation") {
    if (!parseVec(f, "end", r.end)) r.error = "translation has no end";
  } else if (r.op == "contacts") {
    Vec3 dir;
    Real depth[1] = {0};
    if (parseVec(f, "dir", dir) && parseReals(f, "depth", depth, 1)) r.end = r.start + dir * depth[0];
  }
}

void readResult(std::string_view line, TraceRecord& r) {
  Fields f;
  splitFields(line, f);
  if (auto it = f.find("error"); it != f.end()) {
    r.error = it->second;
    return;
  }
  TraceResult& t = r.result;
  t.endPos = r.start;
  t.endAxis = r.trmAxis;
  Real fraction[1];
  if (parseReals(f, "fraction", fraction, 1)) t.fraction = fraction[0];
  parseVec(f, "endpos", t.endPos);
  parseMat(f, "endaxis", t.endAxis);
  // Contacts queries list contacts as type.0, point.0, ...: show the first.
  const std::string suffix = f.count("type") ? "" : ".0";
  ContactInfo& c = t.contact;
  if (auto it = f.find("type" + suffix); it != f.end()) c.type = contactTypeFromName(it->second);
  parseVec(f, "point" + suffix, c.point);
  parseVec(f, "normal" + suffix, c.normal);
  Real dist[1];
  if (parseReals(f, "dist" + suffix, dist, 1)) c.dist = dist[0];
  parseInt(f, "contents" + suffix, c.contents);
  parseInt(f, "modelfeature" + suffix, c.modelFeature);
  parseInt(f, "trmfeature" + suffix, c.trmFeature);
}

}  // namespace

std::vector<TraceRecord> parseTraceRecords(std::string_view queriesText, std::string_view resultsText) {
  std::vector<TraceRecord> records;
  const auto results = splitLines(resultsText);
  if (!queriesText.empty()) {
    const auto queries = splitLines(queriesText);
    for (std::size_t i = 0; i < queries.size(); ++i) {
      TraceRecord& r = records.emplace_back();
      r.queryLine = std::string(queries[i]);
      readQuery(queries[i], r);
      if (i < results.size()) {
        r.resultLine = std::string(results[i]);
        readResult(results[i], r);
      } else {
        r.error = "no result line";
      }
    }
    return records;
  }
  // One file: each query line followed by its result line.
  for (std::size_t i = 0; i < results.size(); ++i) {
    TraceRecord& r = records.emplace_back();
    if (!looksLikeQuery(results[i])) {
      r.resultLine = std::string(results[i]);
      r.error = "result line without a query line";
      continue;
    }
    r.queryLine = std::string(results[i]);
    readQuery(results[i], r);
    if (i + 1 < results.size() && !looksLikeQuery(results[i + 1])) {
      r.resultLine = std::string(results[++i]);
      readResult(r.resultLine, r);
    } else {
      r.error = "no result line";
    }
  }
  return records;
}

}  // namespace cmkit
