// The query format: parsing query lines, running them, formatting results.
#include "cmkit/tools/query_format.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <unordered_map>
#include <vector>

namespace cmkit {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r' || s.back() == '\n'))
    s.remove_suffix(1);
  return s;
}

// Thrown inside this file only, turned into an "error=" line.
struct LineError {
  std::string reason;
};

bool parseFloat(std::string_view text, Real& out) {
  const std::string s(text);
  if (s.empty()) return false;
  char* end = nullptr;
  const float v = std::strtof(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !std::isfinite(v)) return false;
  out = v;
  return true;
}

std::vector<Real> parseFloats(std::string_view text, std::size_t count, const char* key) {
  std::vector<Real> values;
  std::size_t pos = 0;
  while (true) {
    const std::size_t comma = text.find(',', pos);
    Real v;
    if (!parseFloat(text.substr(pos, comma == std::string_view::npos ? std::string_view::npos : comma - pos),
                    v))
      throw LineError{std::string("bad number in ") + key};
    values.push_back(v);
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  if (values.size() != count)
    throw LineError{std::string(key) + " needs " + std::to_string(count) + " numbers"};
  return values;
}

Vec3 parseVec(std::string_view text, const char* key) {
  const auto v = parseFloats(text, 3, key);
  return {v[0], v[1], v[2]};
}

Mat3 parseAxis(std::string_view text, const char* key) {
  const auto v = parseFloats(text, 9, key);
  const Mat3 m{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}};
  auto checked = validateAxis(m);
  if (!checked) throw LineError{std::string(key) + ": " + checked.error().message};
  return *checked;
}

// %.9g, which prints -0 as "-0" as the reference files do.
void appendReal(std::string& out, Real v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", double(v));
  out += buf;
}
void appendVec(std::string& out, const Vec3& v) {
  appendReal(out, v.x);
  out += ',';
  appendReal(out, v.y);
  out += ',';
  appendReal(out, v.z);
}

void appendContact(std::string& out, const CollisionModel& model, const ContactInfo& c,
                   const std::string& suffix) {
  out += "type" + suffix + "=";
  out += toString(c.type);
  out += " point" + suffix + "=";
  appendVec(out, c.point);
  out += " normal" + suffix + "=";
  appendVec(out, c.normal);
  out += " dist" + suffix + "=";
  appendReal(out, c.dist);
  out += " contents" + suffix + "=" + std::to_string(c.contents);
  out += " material" + suffix + "=";
  const std::string_view mat = model.materialName(c.material);
  out += mat.empty() ? std::string_view("-") : mat;
  out += " modelfeature" + suffix + "=" + std::to_string(c.modelFeature);
  out += " trmfeature" + suffix + "=" + std::to_string(c.trmFeature);
}

void appendTrace(std::string& out, const CollisionModel& model, const TraceResult& r) {
  out += "fraction=";
  appendReal(out, r.fraction);
  out += " endpos=";
  appendVec(out, r.endPos);
  out += " endaxis=";
  for (int i = 0; i < 3; ++i) {
    if (i) out += ',';
    appendVec(out, r.endAxis[i]);
  }
  out += ' ';
  appendContact(out, model, r.contact, "");
}

// The key=value pairs of a line.
class Fields {
 public:
  explicit Fields(std::string_view rest) {
    std::size_t pos = 0;
    while (pos < rest.size()) {
      while (pos < rest.size() && (rest[pos] == ' ' || rest[pos] == '\t')) ++pos;
      if (pos >= rest.size()) break;
      std::size_t end = pos;
      while (end < rest.size() && rest[end] != ' ' && rest[end] != '\t') ++end;
      const std::string_view tok = rest.substr(pos, end - pos);
      const std::size_t eq = tok.find('=');
      if (eq == std::string_view::npos || eq == 0)
        throw LineError{"expected key=value, got '" + std::string(tok) + "'"};
      map_[std::string(tok.substr(0, eq))] = tok.substr(eq + 1);
      pos = end;
    }
  }
  std::optional<std::string_view> get(const std::string& key) {
    auto it = map_.find(key);
    if (it == map_.end()) return std::nullopt;
    used_.push_back(key);
    return it->second;
  }
  std::string_view require(const std::string& key) {
    auto v = get(key);
    if (!v) throw LineError{"missing " + key};
    return *v;
  }
  /// Errors on keys the operation does not take.
  void checkAllUsed() const {
    for (const auto& [k, v] : map_) {
      bool used = false;
      for (const auto& u : used_) used |= u == k;
      if (!used) throw LineError{"unknown key " + k};
    }
  }

 private:
  std::unordered_map<std::string, std::string_view> map_;
  std::vector<std::string> used_;
};

const CollisionModel& selectModel(std::span<const ModelPtr> models, Fields& f) {
  if (models.empty()) throw LineError{"no models loaded"};
  const auto name = f.get("model");
  if (!name) return *models[0];
  if (!name->empty() && name->front() == '#') {
    const std::string digits(name->substr(1));
    char* end = nullptr;
    const long n = std::strtol(digits.c_str(), &end, 10);
    if (digits.empty() || *end || n < 0 || std::size_t(n) >= models.size())
      throw LineError{"unknown model " + std::string(*name)};
    return *models[std::size_t(n)];
  }
  for (const ModelPtr& m : models)
    if (m->name == *name) return *m;
  throw LineError{"unknown model " + std::string(*name)};
}

std::uint32_t parseMask(Fields& f) {
  const auto text = f.get("mask");
  if (!text) return contents::kMaskSolid;
  auto mask = parseContentsMask(*text);
  if (!mask) throw LineError{"bad mask"};
  return *mask;
}

std::optional<TraceModel> parseTrm(Fields& f) {
  auto trm = TraceModel::parse(f.require("trm"));
  if (!trm) {
    std::string why = trm.error().message;
    if (why.rfind("degenerate trm", 0) != 0) why = "bad trm (" + why + ")";
    throw LineError{why};
  }
  if (trm->isPoint()) return std::nullopt;
  return std::move(trm).value();
}

Placement parsePlacement(Fields& f) {
  Placement p;
  if (auto o = f.get("origin")) p.origin = parseVec(*o, "origin");
  if (auto a = f.get("modelaxis")) p.axis = parseAxis(*a, "modelaxis");
  return p;
}

// Parses a line into a ParsedQuery (throws LineError).
ParsedQuery parseLine(std::span<const ModelPtr> models, std::string_view line) {
  const std::size_t sp = line.find_first_of(" \t");
  const std::string_view op = line.substr(0, sp);
  Fields f(sp == std::string_view::npos ? std::string_view() : line.substr(sp));
  ParsedQuery q;
  auto modelIndex = [&](const CollisionModel& m) {
    for (std::size_t i = 0; i < models.size(); ++i)
      if (models[i].get() == &m) return i;
    return std::size_t(0);
  };
  if (op == "pointcontents") {
    q.op = QueryOp::PointContents;
    q.position = parseVec(f.require("pos"), "pos");
    q.model = modelIndex(selectModel(models, f));
    q.placement = parsePlacement(f);
    f.checkAllUsed();
    return q;
  }
  if (op == "translation")
    q.op = QueryOp::Translation;
  else if (op == "contents")
    q.op = QueryOp::Contents;
  else if (op == "contacts")
    q.op = QueryOp::Contacts;
  else if (op == "rotation")
    q.op = QueryOp::Rotation;
  else
    throw LineError{"unknown operation '" + std::string(op) + "'"};
  q.trm = parseTrm(f);
  q.position = parseVec(f.require("start"), "start");
  if (auto a = f.get("trmaxis")) q.trmAxis = parseAxis(*a, "trmaxis");
  q.contentMask = parseMask(f);
  q.model = modelIndex(selectModel(models, f));
  q.placement = parsePlacement(f);
  switch (q.op) {
    case QueryOp::Translation:
      q.end = parseVec(f.require("end"), "end");
      break;
    case QueryOp::Contacts:
      q.dir = parseVec(f.require("dir"), "dir");
      if (!parseFloat(f.require("depth"), q.depth)) throw LineError{"bad number in depth"};
      if (auto mx = f.get("max")) {
        Real v;
        if (!parseFloat(*mx, v) || v < 0 || v != std::floor(v) || v > 1e6f) throw LineError{"bad max"};
        q.maxContacts = int(v);
      }
      break;
    case QueryOp::Rotation: {
      const Vec3 axis = parseVec(f.require("rotaxis"), "rotaxis");
      const Vec3 rotOrigin = parseVec(f.require("rotorigin"), "rotorigin");
      Real angle;
      if (!parseFloat(f.require("angle"), angle)) throw LineError{"bad number in angle"};
      if (std::fabs(axis.lengthSquared() - 1) > 0.01f) throw LineError{"rotaxis not unit length"};
      q.rotation = Rotation(rotOrigin, axis, angle);
      break;
    }
    default:
      break;
  }
  f.checkAllUsed();
  return q;
}

}  // namespace

Result<ParsedQuery> parseQueryLine(std::span<const ModelPtr> models, std::string_view line) {
  try {
    return parseLine(models, trim(line));
  } catch (const LineError& e) {
    return Error{e.reason};
  }
}

namespace {

ContactsQuery contactsQuery(const ParsedQuery& q) {
  ContactsQuery cq;
  cq.trm = q.trm ? &*q.trm : nullptr;
  cq.trmAxis = q.trmAxis;
  cq.start = q.position;
  cq.dir = q.dir;
  cq.depth = q.depth;
  cq.contentMask = q.contentMask;
  cq.placement = q.placement;
  cq.maxContacts = q.maxContacts;
  return cq;
}

}  // namespace

double runParsedQueryUnformatted(std::span<const ModelPtr> models, const ParsedQuery& q, QueryWork& work,
                                 std::vector<ContactInfo>& contactsOut) {
  const CollisionModel& m = *models[q.model];
  const TraceModel* trm = q.trm ? &*q.trm : nullptr;
  switch (q.op) {
    case QueryOp::PointContents:
      return pointContents(m, q.position, q.placement);
    case QueryOp::Translation:
      return translate(m, {trm, q.trmAxis, q.position, q.end, q.contentMask, q.placement, false}, work)
          .fraction;
    case QueryOp::Contents:
      return contentsTest(m, {trm, q.trmAxis, q.position, q.contentMask, q.placement}, work).contents;
    case QueryOp::Contacts:
      contactsOut = contacts(m, contactsQuery(q), work).contacts;
      return double(contactsOut.size());
    case QueryOp::Rotation:
      return rotate(m, {trm, q.trmAxis, q.position, q.rotation, q.contentMask, q.placement, false}, work)
          .fraction;
  }
  return 0;
}

std::string runParsedQuery(std::span<const ModelPtr> models, const ParsedQuery& q, QueryWork& work) {
  const CollisionModel& m = *models[q.model];
  const TraceModel* trm = q.trm ? &*q.trm : nullptr;
  std::string out;
  switch (q.op) {
    case QueryOp::PointContents:
      return "contents=" + std::to_string(pointContents(m, q.position, q.placement));
    case QueryOp::Translation:
      appendTrace(out, m,
                  translate(m, {trm, q.trmAxis, q.position, q.end, q.contentMask, q.placement, false}, work));
      return out;
    case QueryOp::Contents: {
      const ContentsResult r =
          contentsTest(m, {trm, q.trmAxis, q.position, q.contentMask, q.placement}, work);
      out = "result=" + std::to_string(r.contents) + " ";
      appendTrace(out, m, r.trace);
      return out;
    }
    case QueryOp::Contacts: {
      const std::vector<ContactInfo> found = contacts(m, contactsQuery(q), work).contacts;
      const int n = int(found.size());
      out = "count=" + std::to_string(n);
      for (int i = 0; i < n; ++i) {
        out += ' ';
        appendContact(out, m, found[std::size_t(i)], "." + std::to_string(i));
      }
      return out;
    }
    case QueryOp::Rotation:
      appendTrace(
          out, m,
          rotate(m, {trm, q.trmAxis, q.position, q.rotation, q.contentMask, q.placement, false}, work));
      return out;
  }
  return "error=unknown operation";
}

const char* toString(QueryOp op) {
  switch (op) {
    case QueryOp::Translation:
      return "translation";
    case QueryOp::Rotation:
      return "rotation";
    case QueryOp::Contents:
      return "contents";
    case QueryOp::PointContents:
      return "pointcontents";
    case QueryOp::Contacts:
      return "contacts";
  }
  return "?";
}

namespace {}  // namespace

bool isQueryLine(std::string_view line) {
  const std::string_view t = trim(line);
  return !t.empty() && t.front() != '#';
}

std::string answerQueryLine(std::span<const ModelPtr> models, std::string_view line, QueryWork& work) {
  auto parsed = parseQueryLine(models, line);
  if (!parsed) return "error=" + parsed.error().message;
  return runParsedQuery(models, *parsed, work);
}

}  // namespace cmkit
