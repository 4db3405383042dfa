// query_format.h: the line-oriented query format (docs/query-format.md, the
// format of the original's reference answers, v1): one query per line, one result
// line per query, so that two implementations can be compared line by line.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cmkit/model.h"
#include "cmkit/query.h"
#include "cmkit/world.h"

namespace cmkit {

/// The contact type of a name written by toString(ContactType) (query.h);
/// nullopt for another text.
std::optional<ContactType> parseContactType(std::string_view name);

/// The operation of a query line.
enum class QueryOp { Translation, Rotation, Contents, PointContents, Contacts };

/// "translation", "rotation", "contents", "pointcontents", "contacts".
const char* toString(QueryOp op);

/// A query line parsed once (for running it many times, e.g. benchmarks).
struct ParsedQuery {
  /// The kind of query.
  QueryOp op = QueryOp::Translation;
  std::optional<TraceModel> trm;  ///< empty: a point
  std::string trmSpec;            ///< the trm= field as written (e.g. "box:-16,-16,0,16,16,72")
  /// Orientation of the trace model.
  Mat3 trmAxis;
  Vec3 position;         ///< start (pos for pointcontents)
  Vec3 end;              ///< translation
  Vec3 dir;              ///< contacts
  Real depth = 0;        ///< contacts
  int maxContacts = 16;  ///< contacts
  Rotation rotation;     ///< rotation; contacts when `rotational`
  /// contacts: along `rotation` (the line has rotorigin=, rotaxis=, angle=);
  /// its result line gives each contact's angle (angle.i=).
  bool rotational = false;
  /// Content flags the queries collide with.
  std::uint32_t contentMask = contents::kMaskSolid;
  std::size_t model = 0;  ///< index into the models
  /// Where the model is placed in the world.
  Placement placement;
};

/// Parses a query line; the error message is the line's "error=" reason.
Result<ParsedQuery> parseQueryLine(std::span<const ModelPtr> models, std::string_view line);

/// Runs a parsed query and formats its result line.
std::string runParsedQuery(std::span<const ModelPtr> models, const ParsedQuery& query, QueryWork& work);

/// Runs a parsed query without formatting its result (what benchmarks time).
/// Returns the fraction (translation, rotation), the contents (contents,
/// pointcontents) or the number of contacts.
double runParsedQueryUnformatted(std::span<const ModelPtr> models, const ParsedQuery& query, QueryWork& work);
/// The same, contacts collected in `contacts` (cleared first; its memory kept
/// from query to query, as a game loop would keep it).
double runParsedQueryUnformatted(std::span<const ModelPtr> models, const ParsedQuery& query, QueryWork& work,
                                 std::vector<ContactInfo>& contacts);

/// True for lines that hold a query (not blank, not a # comment).
bool isQueryLine(std::string_view line);

/// Runs one query line against the models (in load order; the first is the
/// default) and returns its result line, or "error=<reason>" for a line that
/// cannot be run (bad syntax, unknown model, degenerate trace model).
std::string answerQueryLine(std::span<const ModelPtr> models, std::string_view line, QueryWork& work);

/// Runs one query line against a whole World (cmkit query --world): the
/// closest answer over its entities (world.h), with entity=NAME after the
/// fields of a result with a hit (after each contact's, numbered, for
/// contacts). model=, origin= and modelaxis= are errors on such a line.
std::string answerWorldQueryLine(const World& world, std::string_view line, WorldQueryWork& work);

}  // namespace cmkit
