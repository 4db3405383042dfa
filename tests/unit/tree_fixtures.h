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

/// The chain of deepChainCm without its brush, and one brush at every split:
/// brush i spans x i - 0.5 .. 1005 (y and z 0..10), so it straddles node
/// i's split (x = i) and lies in front of every split above it, and the
/// filter keeps it at node i. Its contents: contentsOf(i).
template <class ContentsOf>
ModelPtr brushAtEveryNode(int depth, ContentsOf contentsOf) {
  std::string nodes, brushes;
  for (int i = 0; i < depth; ++i) nodes += "( 0 " + std::to_string(i) + " ) ";
  for (int i = 0; i <= depth; ++i) nodes += "( -1 0 ) ";
  for (int i = 0; i < depth; ++i) {
    const std::string minX = i == 0 ? "-0.5" : std::to_string(i - 1) + ".5";  // i - 0.5
    brushes += " 6 { ( 1 0 0 ) 1005 ( -1 0 0 ) " + (i == 0 ? std::string("0.5") : "-" + minX) +
               " ( 0 1 0 ) 10 ( 0 -1 0 ) 0 ( 0 0 1 ) 10 ( 0 0 -1 ) 0 } ( " + minX + " 0 0 ) ( 1005 10 10 ) " +
               std::to_string(contentsOf(i)) + "\n";
  }
  auto f = parseCmText("CM \"1.00\" 0\ncollisionModel \"deep\" {\n  nodes { " + nodes + "}\n  brushes {\n" +
                           brushes + "  }\n}\n",
                       "deep.cm", MaterialTable{});
  EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().toString());
  return f.ok() ? f->models.front() : nullptr;
}

}  // namespace cmkit::test
