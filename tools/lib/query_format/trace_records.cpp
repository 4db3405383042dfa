// Reading query lines and their result lines back for drawing
// (docs/query-format.md). Tolerant: a line that cannot be read gives a
// record with an error, never an exception or an abort.
#include <string>

#include "cmkit/tools/debug_draw.h"
#include "cmkit/tools/query_format.h"
#include "io/fields.h"
#include "query_format/result_fields.h"

namespace cmkit {
namespace {

using detail::Fields;
using detail::Finite;

std::vector<std::string_view> splitLines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t nl = text.find('\n', pos);
    if (nl == std::string_view::npos) nl = text.size();
    const std::string_view line = detail::trimLine(text.substr(pos, nl - pos));
    if (!line.empty() && line.front() != '#') lines.push_back(line);
    pos = nl + 1;
  }
  return lines;
}

/// True for a query line (it starts with an operation name, not key=value).
bool looksLikeQuery(std::string_view line) {
  return detail::splitWord(line).first.find('=') == std::string_view::npos;
}

// Reads the fields of a result line (result_fields.h) that are present and
// well-formed; the others keep their values.
class ResultReader {
 public:
  ResultReader(const Fields& f, std::string suffix = {}) : f_(f), suffix_(std::move(suffix)) {}

  void operator()(const char* key, Real& out) {
    if (const auto v = value(key)) out = detail::parseReal(*v, Finite::NotRequired).value_or(out);
  }
  void operator()(const char* key, Vec3& out) {
    if (const auto v = value(key)) out = detail::parseVec3(*v, Finite::NotRequired).value_or(out);
  }
  void operator()(const char* key, Mat3& out) {
    if (const auto v = value(key)) out = detail::parseMat3(*v, Finite::NotRequired).value_or(out);
  }
  void operator()(const char* key, ContactType& out) {
    if (const auto v = value(key)) out = parseContactType(*v).value_or(ContactType::None);
  }
  template <typename Int>
  void operator()(const char* key, Int& out) {
    if (const auto v = value(key)) out = Int(detail::parseInt(*v).value_or(0));
  }
  void material(const char*, std::int32_t&) {}  // a name; the index is the model's
  void entity(const char* key, std::string& out) {
    if (const auto v = value(key)) out = std::string(*v);
  }

 private:
  std::optional<std::string_view> value(const char* key) const { return f_.get(key + suffix_); }

  const Fields& f_;
  std::string suffix_;
};

void readQuery(std::string_view line, TraceRecord& r) {
  auto [op, rest] = detail::splitWord(line);
  if (op.find('=') != std::string_view::npos) {  // no operation, only fields
    op = {};
    rest = line;
  }
  const Fields f(rest);
  r.op = std::string(op);
  auto vec = [&](const char* key, Vec3& out) {
    const auto text = f.get(key);
    const auto v = text ? detail::parseVec3(*text, Finite::NotRequired) : std::nullopt;
    if (v) out = *v;
    return v.has_value();
  };
  if (r.op == "pointcontents") {
    vec("pos", r.start);
    r.end = r.start;
    return;
  }
  if (auto text = f.get("trm")) {
    auto trm = TraceModel::parse(*text);
    if (trm) {
      r.trm = std::move(*trm);
    } else {
      r.error = "bad trm: " + trm.error().message;
    }
  }
  if (auto text = f.get("trmaxis"))
    r.trmAxis = detail::parseMat3(*text, Finite::NotRequired).value_or(r.trmAxis);
  if (!vec("start", r.start)) r.error = "query has no start";
  r.end = r.start;
  if (r.op == "translation") {
    if (!vec("end", r.end)) r.error = "translation has no end";
  } else if (r.op == "contacts") {
    Vec3 dir;
    const auto depth = detail::parseReal(f.value("depth"), Finite::NotRequired);
    if (vec("dir", dir) && depth) r.end = r.start + dir * *depth;
  }
}

void readResult(std::string_view line, TraceRecord& r) {
  const Fields f(line);
  if (auto error = f.get("error")) {
    r.error = std::string(*error);
    return;
  }
  TraceResult& t = r.result;
  t.endPos = r.start;
  t.endAxis = r.trmAxis;
  ResultReader trace(f);
  detail::visitTraceFields(trace, t);
  // Contacts queries list contacts as type.0, point.0, ...: show the first.
  ResultReader contact(f, f.has("type") ? "" : ".0");
  detail::visitContactFields(contact, t.contact);
  detail::visitRotationContactFields(contact, t.contact);  // contacts along a rotation only
  detail::visitEntityField(contact, r.entity);             // world queries only
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
