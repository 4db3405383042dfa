// Shared by the fuzz targets: what to do with whatever a parser accepted.
//
// A parser either returns an error (fine: that is its job) or a value; the
// targets then push the value through the rest of the pipeline with small,
// bounded work, so that the sanitizers see every stage on odd input:
// models are validated (the builder and the reader must only produce valid
// models) and queried (traces, contents, contacts, rotation).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "cmkit/model.h"

namespace cmkit::fuzz {

/// Inputs longer than this are skipped: building a model is superlinear and
/// the point is odd input, not big input.
inline constexpr std::size_t kMaxInputBytes = 64 * 1024;

/// Runs a few queries of every kind on each of the first 8 models (bounded
/// work).
void exerciseModels(std::span<const ModelPtr> models);

/// Checks a model the library produced; aborts (a finding) when its
/// structure is broken (odd geometry is allowed).
void requireValid(const CollisionModel& model, std::string_view where);

}  // namespace cmkit::fuzz

/// The libFuzzer entry point every target defines.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
