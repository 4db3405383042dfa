// query_file.h: the line-oriented query format (docs/query-format.md, the
// same as shared/spec/query-format.md v1): one query per line, one result
// line per query, so that two implementations can be compared line by line.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "cmkit/model.h"
#include "cmkit/query.h"

namespace cmkit {

/// True for lines that hold a query (not blank, not a # comment).
bool isQueryLine(std::string_view line);

/// Runs one query line against the models (in load order; the first is the
/// default) and returns its result line, or "error=<reason>" for a line that
/// cannot be run (bad syntax, unknown model, degenerate trace model).
std::string answerQueryLine(std::span<const ModelPtr> models, std::string_view line, QueryWork& work);

}  // namespace cmkit
