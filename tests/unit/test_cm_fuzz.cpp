// Malformed .cm files: every truncation and seeded random token corruptions
// of a real file give an error (never a crash, never a partial model).
// Worth running under ASan+UBSan (see DEVELOPERS.md / the cm-asan build).
#include <gtest/gtest.h>

#include <random>

#include "cmkit/cm_file.h"
#include "cmkit/validate.h"
#include "test_support.h"

namespace cmkit {
namespace {

std::string testCm() { return test::readFile(test::testDataDir() / "cm" / "opentechbfg_test.cm"); }

// Byte ranges of the whitespace-separated tokens outside /* */ comments.
std::vector<std::pair<std::size_t, std::size_t>> tokens(const std::string& text) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    if (text.compare(i, 2, "/*") == 0) {
      const std::size_t end = text.find("*/", i + 2);
      i = end == std::string::npos ? text.size() : end + 2;
      continue;
    }
    const std::size_t start = i;
    while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    if (i > start) out.emplace_back(start, i - start);
  }
  return out;
}

TEST(CmFuzz, EveryTruncationIsAnErrorOrAWholeFile) {
  const std::string text = testCm();
  ASSERT_FALSE(text.empty());
  const MaterialTable materials;
  // Prefixes that are complete files: the header alone (with some CRC digits)
  // and the whole model.
  const std::size_t modelStart = text.find("collisionModel");
  const std::size_t lastBrace = text.rfind('}');
  int errors = 0;
  for (std::size_t len = 0; len < text.size(); ++len) {
    Result<CmFile> r = parseCmText(std::string_view(text).substr(0, len), "t.cm", materials);
    if (!r.ok()) {
      ++errors;
      EXPECT_GT(r.error().line, 0);
      continue;
    }
    if (r->models.empty()) {
      EXPECT_LE(len, modelStart) << "a prefix of " << len << " bytes parsed without its model";
    } else {
      EXPECT_GT(len, lastBrace) << "a prefix of " << len << " bytes gave a partial model";
    }
  }
  EXPECT_GT(errors, int(text.size()) - 40);
}

// Replacing one token by one that cannot stand there always fails.
TEST(CmFuzz, RandomTokenCorruptionsAreErrors) {
  const std::string text = testCm();
  const auto toks = tokens(text);
  const MaterialTable materials;
  std::mt19937 rng(20261122);
  int tried = 0;
  for (int round = 0; round < 400; ++round) {
    const auto [at, len] = toks[rng() % toks.size()];
    const std::string_view tok(text.data() + at, len);
    const bool number = (tok[0] >= '0' && tok[0] <= '9') || tok[0] == '-';
    // Choices that are wrong wherever the original token stood.
    std::vector<std::string> wrong;
    if (number) {
      wrong = {"@", "(", "}", "\"x\"", "abc", "1e40", "-1e40"};
    } else if (tok == "(") {
      wrong = {")", "{", "7x", "@"};
    } else if (tok == ")") {
      wrong = {"(", "{", "x", "@"};
    } else if (tok == "{") {
      wrong = {"(", "}", "@"};
    } else if (tok == "}") {
      wrong = {")", "(", "@"};
    } else if (tok[0] == '"') {
      wrong = {"7", "(", "\"unterminated"};
    } else {
      wrong = {"bogus", "7", "{"};
    }
    const std::string replacement = wrong[rng() % wrong.size()];
    std::string bad = text;
    bad.replace(at, len, replacement);
    Result<CmFile> r = parseCmText(bad, "t.cm", materials);
    ++tried;
    EXPECT_FALSE(r.ok()) << "token '" << tok << "' at " << at << " replaced by '" << replacement
                         << "' parsed";
  }
  EXPECT_GT(tried, 300);
}

// Deleting a token or flipping bytes: an error, or (rarely, e.g. a deleted
// memory hint) a complete file that is written back and read again.
TEST(CmFuzz, RandomDeletionsAndByteFlipsNeverCrash) {
  const std::string text = testCm();
  const auto toks = tokens(text);
  const MaterialTable materials;
  std::mt19937 rng(7);
  for (int round = 0; round < 300; ++round) {
    std::string bad = text;
    if (round % 2 == 0) {
      const auto [at, len] = toks[rng() % toks.size()];
      bad.erase(at, len);
    } else {
      for (int k = 0; k < 3; ++k) bad[rng() % bad.size()] = char(rng() % 256);
    }
    Result<CmFile> r = parseCmText(bad, "t.cm", materials);
    if (!r.ok()) continue;
    ASSERT_EQ(r->models.size(), 1u);
    (void)validateModel(*r->models[0]);
    EXPECT_TRUE(parseCmText(writeCmText(r->models, r->crc), "again", materials).ok());
  }
}

TEST(CmFuzz, DeepNodeTreesDoNotExhaustTheStack) {
  std::string text = "CM \"1.00\" 0 collisionModel \"deep\" { nodes {";
  const int depth = 200000;
  for (int i = 0; i < depth; ++i) text += " ( 0 " + std::to_string(i) + " ) ( -1 0 )";
  text += " ( -1 0 ) } }";
  Result<CmFile> r = parseCmText(text, "deep.cm", MaterialTable{});
  ASSERT_TRUE(r.ok()) << r.error().toString();
  EXPECT_EQ(r->models[0]->nodes().size(), std::size_t(2 * depth + 1));
  // A truncated one is an error.
  EXPECT_FALSE(parseCmText(text.substr(0, text.size() - 12), "deep.cm", MaterialTable{}).ok());
}

}  // namespace
}  // namespace cmkit
