// Models with unusual trees for the query tests.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "cmkit/cm_file.h"
#include "cmkit/materials.h"
#include "cmkit/model.h"

namespace cmkit::test {

/// A .cm model whose tree is a chain of `depth` splits on x (node i splits at
/// x = i, its front child is node i + 1, its back child an empty leaf), with
/// one solid box brush x 1000..1010, y and z 0..10, which is filtered into the
/// deepest leaf.
inline std::string deepChainCm(int depth) {
  std::string nodes;
  for (int i = 0; i < depth; ++i) nodes += "( 0 " + std::to_string(i) + " ) ";
  for (int i = 0; i <= depth; ++i) nodes += "( -1 0 ) ";  // the deepest front leaf, then the back leaves
  return "CM \"1.00\" 0\ncollisionModel \"deep\" {\n  nodes { " + nodes +
         "}\n"
         "  brushes { 6 { ( 1 0 0 ) 1010 ( -1 0 0 ) -1000 ( 0 1 0 ) 10 ( 0 -1 0 ) 0 ( 0 0 1 ) 10 "
         "( 0 0 -1 ) 0 } ( 1000 0 0 ) ( 1010 10 10 ) 1 }\n}\n";
}

inline ModelPtr deepChain(int depth) {
  auto f = parseCmText(deepChainCm(depth), "deep.cm", MaterialTable{});
  EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().toString());
  return f.ok() ? f->models.front() : nullptr;
}

}  // namespace cmkit::test
