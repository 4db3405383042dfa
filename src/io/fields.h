// Internal: the pieces of the query-line format (docs/query-format.md) that
// every reader of it shares: trimming, the operation word, key=value fields
// and the number lists of values ("1,2,3"). The readers: query lines
// (query_file.cpp), query and result lines read back for drawing
// (trace_records.cpp), trace-model specs (trace_model_spec.cpp), and the
// tests that compare result lines.
//
// Numbers in these formats are read with strtof (correctly rounded; it also
// takes a leading '+', exponents, hex floats, inf and nan), the whole text
// of each number must be used.
#pragma once

#include <optional>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "cmkit/math.h"
#include "cmkit/query.h"

namespace cmkit::detail {

/// `s` without spaces, tabs, CRs and LFs at either end, and without a
/// leading UTF-8 byte-order mark (the first line of some files).
std::string_view trimLine(std::string_view s);

/// The first word of a line (up to a space or tab) and the rest after it.
std::pair<std::string_view, std::string_view> splitWord(std::string_view line);

/// The key=value fields of a text, tokens separated by spaces or tabs. Keys
/// and values view the text. A repeated key: the later value counts.
class Fields {
 public:
  explicit Fields(std::string_view text);

  std::optional<std::string_view> get(std::string_view key) const;
  bool has(std::string_view key) const { return get(key).has_value(); }
  /// The value of `key`, empty when absent.
  std::string_view value(std::string_view key) const { return get(key).value_or(std::string_view()); }
  /// The fields in the order of the text (repeats included).
  std::span<const std::pair<std::string_view, std::string_view>> all() const { return fields_; }
  /// The first token that is not key=value (no '=', or nothing before it);
  /// empty when there is none.
  std::string_view stray() const { return stray_; }

 private:
  std::vector<std::pair<std::string_view, std::string_view>> fields_;
  std::string_view stray_;
};

/// Whether non-finite numbers (inf, nan) are accepted.
enum class Finite { Required, NotRequired };

/// One number, all of `text` (strtof).
std::optional<Real> parseReal(std::string_view text, Finite finite = Finite::Required);

/// Comma-separated numbers appended to `out`. False at the first bad one
/// (empty included), which `bad` then views.
bool parseRealList(std::string_view text, std::vector<Real>& out, std::string_view* bad = nullptr,
                   Finite finite = Finite::Required);

/// Exactly 3 (a vector) or 9 (a matrix, rows first) comma-separated numbers.
std::optional<Vec3> parseVec3(std::string_view text, Finite finite = Finite::Required);
std::optional<Mat3> parseMat3(std::string_view text, Finite finite = Finite::Required);

/// A decimal integer, all of `text` (strtoll: an optional sign).
std::optional<long long> parseInt(std::string_view text);

/// Like sscanf("%f %f ..."), as the original reads the numbers of an entity
/// key ("origin" "1 2 3"): whitespace-separated numbers, correctly rounded
/// (from_chars; a leading '+' skipped), stopping at the first thing that is
/// not a number. The values read replace the first entries of `out`, the
/// rest keep theirs.
void scanReals(std::string_view text, std::span<float> out);

/// False when one of the first `count` numbers that scanReals would read is
/// not a finite float (inf, nan, or beyond the float range like 1e999;
/// scanReals would skip those or take them as they are).
bool scannedRealsFinite(std::string_view text, std::size_t count);

}  // namespace cmkit::detail
