// The query format: parsing query lines, running them, formatting results.
#include "cmkit/tools/query_format.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <utility>
#include <vector>

#include "io/fields.h"
#include "query_format/result_fields.h"

namespace cmkit {
namespace {

using detail::Fields;

// Thrown inside this file only, turned into an "error=" line.
struct LineError {
  std::string reason;
};

Real parseFloat(std::string_view text, const char* key) {
  const auto v = detail::parseReal(text);
  if (!v) throw LineError{std::string("bad number in ") + key};
  return *v;
}

std::vector<Real> parseFloats(std::string_view text, std::size_t count, const char* key) {
  std::vector<Real> values;
  if (!detail::parseRealList(text, values)) throw LineError{std::string("bad number in ") + key};
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

// Writes the fields of a result line (result_fields.h), each "key=value"
// after a space but the first.
class ResultWriter {
 public:
  ResultWriter(std::string& out, const CollisionModel& model, std::string suffix = {})
      : out_(out), model_(model), suffix_(std::move(suffix)) {}

  void operator()(const char* key, Real v) {
    start(key);
    appendReal(v);
  }
  void operator()(const char* key, const Vec3& v) {
    start(key);
    appendVec(v);
  }
  void operator()(const char* key, const Mat3& m) {
    start(key);
    for (int i = 0; i < 3; ++i) {
      if (i) out_ += ',';
      appendVec(m[i]);
    }
  }
  void operator()(const char* key, ContactType type) {
    start(key);
    out_ += toString(type);
  }
  void operator()(const char* key, std::uint32_t v) {
    start(key);
    out_ += std::to_string(v);
  }
  void operator()(const char* key, std::int32_t v) {
    start(key);
    out_ += std::to_string(v);
  }
  void material(const char* key, std::int32_t index) {
    start(key);
    const std::string_view name = model_.materialName(index);
    out_ += name.empty() ? std::string_view("-") : name;
  }
  void entity(const char* key, const std::string& name) {
    start(key);
    out_ += name;
  }

 private:
  void start(const char* key) {
    if (!first_) out_ += ' ';
    first_ = false;
    out_ += key;
    out_ += suffix_;
    out_ += '=';
  }
  // %.9g, which prints -0 as "-0" as the reference files do.
  void appendReal(Real v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", double(v));
    out_ += buf;
  }
  void appendVec(const Vec3& v) {
    appendReal(v.x);
    out_ += ',';
    appendReal(v.y);
    out_ += ',';
    appendReal(v.z);
  }

  std::string& out_;
  const CollisionModel& model_;
  std::string suffix_;
  bool first_ = true;
};

void appendTrace(std::string& out, const CollisionModel& model, const TraceResult& r) {
  ResultWriter w(out, model);
  detail::visitTraceFields(w, r);
  detail::visitContactFields(w, r.contact);
}

// The key=value fields of a query line, each to be used by the operation.
class QueryFields {
 public:
  explicit QueryFields(std::string_view rest) : fields_(rest) {
    if (!fields_.stray().empty())
      throw LineError{"expected key=value, got '" + std::string(fields_.stray()) + "'"};
  }
  std::optional<std::string_view> get(std::string_view key) {
    const auto v = fields_.get(key);
    if (v) used_.push_back(key);
    return v;
  }
  /// Whether the line has `key` (without using it).
  bool has(std::string_view key) const { return fields_.has(key); }
  std::string_view require(std::string_view key) {
    auto v = get(key);
    if (!v) throw LineError{"missing " + std::string(key)};
    return *v;
  }
  /// Errors on keys the operation does not take.
  void checkAllUsed() const {
    for (const auto& [k, v] : fields_.all()) {
      if (std::find(used_.begin(), used_.end(), k) == used_.end())
        throw LineError{"unknown key " + std::string(k)};
    }
  }

 private:
  Fields fields_;
  std::vector<std::string_view> used_;
};

const CollisionModel& selectModel(std::span<const ModelPtr> models, QueryFields& f) {
  if (models.empty()) throw LineError{"no models loaded"};
  const auto name = f.get("model");
  if (!name) return *models[0];
  if (!name->empty() && name->front() == '#') {
    const std::optional<long long> n = detail::parseInt(name->substr(1));
    if (!n || *n < 0 || std::size_t(*n) >= models.size())
      throw LineError{"unknown model " + std::string(*name)};
    return *models[std::size_t(*n)];
  }
  for (const ModelPtr& m : models)
    if (m->name() == *name) return *m;
  throw LineError{"unknown model " + std::string(*name)};
}

std::uint32_t parseMask(QueryFields& f) {
  const auto text = f.get("mask");
  if (!text) return contents::kMaskSolid;
  auto mask = parseContentsMask(*text);
  if (!mask) throw LineError{"bad mask"};
  return *mask;
}

std::optional<TraceModel> parseTrm(QueryFields& f) {
  auto trm = TraceModel::parse(f.require("trm"));
  if (!trm) {
    std::string why = trm.error().message;
    if (why.rfind("degenerate trm", 0) != 0) why = "bad trm (" + why + ")";
    throw LineError{why};
  }
  if (trm->isPoint()) return std::nullopt;
  return std::move(trm).value();
}

Placement parsePlacement(QueryFields& f) {
  Placement p;
  if (auto o = f.get("origin")) p.origin = parseVec(*o, "origin");
  if (auto a = f.get("modelaxis")) p.axis = parseAxis(*a, "modelaxis");
  return p;
}

// The rotation of a rotation line, or of a contacts line along a rotation:
// rotorigin=, rotaxis= (of unit length within 0.01 of its square) and angle=.
Rotation parseRotation(QueryFields& f) {
  const Vec3 axis = parseVec(f.require("rotaxis"), "rotaxis");
  const Vec3 rotOrigin = parseVec(f.require("rotorigin"), "rotorigin");
  const Real angle = parseFloat(f.require("angle"), "angle");
  if (std::fabs(axis.lengthSquared() - 1) > 0.01f) throw LineError{"rotaxis not unit length"};
  return Rotation(rotOrigin, axis, angle);
}

// Parses a line into a ParsedQuery (throws LineError).
ParsedQuery parseLine(std::span<const ModelPtr> models, std::string_view line) {
  const auto [op, rest] = detail::splitWord(line);
  QueryFields f(rest);
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
  q.trmSpec = std::string(*f.get("trm"));
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
      // Along a rotation when any of its keys is there (then all three must
      // be); dir and depth may then be left out (zero). Both a translation
      // and a rotation: the library refuses the query (MixedMotion).
      q.rotational = f.has("rotorigin") || f.has("rotaxis") || f.has("angle");
      if (q.rotational) q.rotation = parseRotation(f);
      if (!q.rotational || f.has("dir")) q.dir = parseVec(f.require("dir"), "dir");
      if (!q.rotational || f.has("depth")) q.depth = parseFloat(f.require("depth"), "depth");
      if (auto mx = f.get("max")) {
        const std::optional<Real> v = detail::parseReal(*mx);
        if (!v || *v < 0 || *v != std::floor(*v) || *v > 1e6f) throw LineError{"bad max"};
        q.maxContacts = int(*v);
      }
      break;
    case QueryOp::Rotation:
      q.rotation = parseRotation(f);
      break;
    default:
      break;
  }
  f.checkAllUsed();
  return q;
}

}  // namespace

Result<ParsedQuery> parseQueryLine(std::span<const ModelPtr> models, std::string_view line) {
  try {
    return parseLine(models, detail::trimLine(line));
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
  if (q.rotational) cq.rotation = q.rotation;
  return cq;
}

}  // namespace

double runParsedQueryUnformatted(std::span<const ModelPtr> models, const ParsedQuery& q, QueryWork& work) {
  std::vector<ContactInfo> found;
  return runParsedQueryUnformatted(models, q, work, found);
}

double runParsedQueryUnformatted(std::span<const ModelPtr> models, const ParsedQuery& q, QueryWork& work,
                                 std::vector<ContactInfo>& found) {
  const CollisionModel& m = *models[q.model];
  const TraceModel* trm = q.trm ? &*q.trm : nullptr;
  switch (q.op) {
    case QueryOp::PointContents:
      return pointContents(m, {q.position, q.placement}, work).contents;
    case QueryOp::Translation:
      return translate(m, {trm, q.trmAxis, q.position, q.end, q.contentMask, q.placement, false}, work)
          .fraction;
    case QueryOp::Contents:
      return contentsTest(m, {trm, q.trmAxis, q.position, q.contentMask, q.placement}, work).contents;
    case QueryOp::Contacts:
      contacts(m, contactsQuery(q), work, found);
      return double(found.size());
    case QueryOp::Rotation:
      return rotate(m, {trm, q.trmAxis, q.position, q.rotation, q.contentMask, q.placement, false}, work)
          .fraction;
  }
  return 0;
}

namespace {

// The line of a query the library refused (QueryStatus).
std::string refusedLine(QueryStatus status) { return std::string("error=refused: ") + toString(status); }

}  // namespace

std::string runParsedQuery(std::span<const ModelPtr> models, const ParsedQuery& q, QueryWork& work) {
  const CollisionModel& m = *models[q.model];
  const TraceModel* trm = q.trm ? &*q.trm : nullptr;
  std::string out;
  switch (q.op) {
    case QueryOp::PointContents:
      // (A refused point reads as contents 0, as before there was a status.)
      return "contents=" + std::to_string(pointContents(m, {q.position, q.placement}, work).contents);
    case QueryOp::Translation: {
      const TraceResult r =
          translate(m, {trm, q.trmAxis, q.position, q.end, q.contentMask, q.placement, false}, work);
      if (r.status != QueryStatus::Ok) return refusedLine(r.status);
      appendTrace(out, m, r);
      return out;
    }
    case QueryOp::Contents: {
      const ContentsResult r =
          contentsTest(m, {trm, q.trmAxis, q.position, q.contentMask, q.placement}, work);
      if (r.status != QueryStatus::Ok) return refusedLine(r.status);
      out = "result=" + std::to_string(r.contents) + " ";
      appendTrace(out, m, r.trace);
      return out;
    }
    case QueryOp::Contacts: {
      const ContactsResult r = contacts(m, contactsQuery(q), work);
      if (r.status != QueryStatus::Ok) return refusedLine(r.status);
      const std::vector<ContactInfo>& found = r.contacts;
      const int n = int(found.size());
      out = "count=" + std::to_string(n);
      for (int i = 0; i < n; ++i) {
        out += ' ';
        ResultWriter w(out, m, "." + std::to_string(i));
        detail::visitContactFields(w, found[std::size_t(i)]);
        if (q.rotational) detail::visitRotationContactFields(w, found[std::size_t(i)]);
      }
      return out;
    }
    case QueryOp::Rotation: {
      const TraceResult r =
          rotate(m, {trm, q.trmAxis, q.position, q.rotation, q.contentMask, q.placement, false}, work);
      if (r.status != QueryStatus::Ok) return refusedLine(r.status);
      appendTrace(out, m, r);
      return out;
    }
  }
  return "error=unknown operation";
}

namespace {

// The name written for a world answer's entity.
const std::string& entityName(const World& world, EntityId id) { return world.entity(id)->name; }

// The trace fields and, on a hit, entity=NAME (materials named from the hit
// entity's model).
void appendWorldTrace(std::string& out, const World& world, const TraceResult& r, EntityId id,
                      const CollisionModel& fallback) {
  const CollisionModel& model = id != kNoEntity ? *world.entity(id)->model : fallback;
  ResultWriter w(out, model);
  detail::visitTraceFields(w, r);
  detail::visitContactFields(w, r.contact);
  if (id != kNoEntity) detail::visitEntityField(w, entityName(world, id));
}

}  // namespace

std::string answerWorldQueryLine(const World& world, std::string_view line, WorldQueryWork& work) {
  // Parsed against one model (the world model, or any entity's) for the
  // line's syntax; model=, origin= and modelaxis= do not apply.
  const std::vector<EntityId> ids = world.entityIds();
  if (ids.empty()) return "error=no entities in the world";
  const ModelPtr model = world.entity(kWorldspawnEntity) ? world.entity(kWorldspawnEntity)->model
                                                         : world.entity(ids.front())->model;
  const std::string_view trimmed = detail::trimLine(line);
  {
    const Fields f(detail::splitWord(trimmed).second);
    if (f.has("model") || f.has("origin") || f.has("modelaxis"))
      return "error=model=, origin= and modelaxis= do not apply to a world query (entities are placed by the "
             "map)";
  }
  const std::span<const ModelPtr> models(&model, 1);
  auto parsed = parseQueryLine(models, trimmed);
  if (!parsed) return "error=" + parsed.error().message;
  const ParsedQuery& q = *parsed;
  const TraceModel* trm = q.trm ? &*q.trm : nullptr;
  std::string out;
  switch (q.op) {
    case QueryOp::PointContents: {
      const WorldPointContentsResult r = world.pointContents({q.position, {}}, work);
      out = "contents=" + std::to_string(r.contents);
      if (r.entity != kNoEntity) out += " entity=" + entityName(world, r.entity);
      return out;
    }
    case QueryOp::Translation: {
      const WorldTraceResult r =
          world.translate({trm, q.trmAxis, q.position, q.end, q.contentMask, {}, false}, work);
      if (r.trace.status != QueryStatus::Ok) return refusedLine(r.trace.status);
      appendWorldTrace(out, world, r.trace, r.entity, *model);
      return out;
    }
    case QueryOp::Contents: {
      const WorldContentsResult r = world.contentsTest({trm, q.trmAxis, q.position, q.contentMask, {}}, work);
      if (r.result.status != QueryStatus::Ok) return refusedLine(r.result.status);
      out = "result=" + std::to_string(r.result.contents) + " ";
      appendWorldTrace(out, world, r.result.trace, r.entity, *model);
      return out;
    }
    case QueryOp::Contacts: {
      const WorldContactsResult r = world.contacts(contactsQuery(q), work);
      if (r.status != QueryStatus::Ok) return refusedLine(r.status);
      out = "count=" + std::to_string(r.contacts.size());
      for (std::size_t i = 0; i < r.contacts.size(); ++i) {
        const WorldContact& c = r.contacts[i];
        out += ' ';
        ResultWriter w(out, *world.entity(c.entity)->model, "." + std::to_string(i));
        detail::visitContactFields(w, c.contact);
        if (q.rotational) detail::visitRotationContactFields(w, c.contact);
        detail::visitEntityField(w, entityName(world, c.entity));
      }
      return out;
    }
    case QueryOp::Rotation: {
      const WorldTraceResult r =
          world.rotate({trm, q.trmAxis, q.position, q.rotation, q.contentMask, {}, false}, work);
      if (r.trace.status != QueryStatus::Ok) return refusedLine(r.trace.status);
      appendWorldTrace(out, world, r.trace, r.entity, *model);
      return out;
    }
  }
  return "error=unknown operation";
}

std::optional<ContactType> parseContactType(std::string_view name) {
  for (const ContactType t :
       {ContactType::None, ContactType::Edge, ContactType::ModelVertex, ContactType::TrmVertex})
    if (name == toString(t)) return t;
  return std::nullopt;
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

bool isQueryLine(std::string_view line) {
  const std::string_view t = detail::trimLine(line);
  return !t.empty() && t.front() != '#';
}

std::string answerQueryLine(std::span<const ModelPtr> models, std::string_view line, QueryWork& work) {
  auto parsed = parseQueryLine(models, line);
  if (!parsed) return "error=" + parsed.error().message;
  return runParsedQuery(models, *parsed, work);
}

}  // namespace cmkit
