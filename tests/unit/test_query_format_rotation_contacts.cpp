// Contacts along a rotation in the query-line format (query_format.h,
// docs/query-format.md): `contacts ... rotorigin= rotaxis= angle=`, the
// contacts' angle.i= fields, the MixedMotion refusal, and the result line
// read back (parseTraceRecords) as the C++ API's contacts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <string>
#include <type_traits>
#include <vector>

#include "cmkit/query.h"
#include "cmkit/tools/debug_draw.h"
#include "cmkit/tools/query_format.h"
#include "model_fixtures.h"

using namespace cmkit;
using cmkit::test::ModelMaker;

namespace {

/// A number written with %.9g and read back: the float itself in the float
/// build; in the double build within float precision (the trace-record
/// reader keeps floats).
void expectPrintedAs(Real read, Real value) {
  if constexpr (std::is_same_v<Real, float>) {
    EXPECT_EQ(read, value);
  } else {
    EXPECT_NEAR(read, value, 1e-6 * std::max(Real(1), std::fabs(value)));
  }
}

// The scene of test_query_contacts_rotation.cpp: a bar 60 long, 4 wide, 16
// high turning about the z axis through its centre into two walls, y <= -10
// for x >= 0 and y >= 14 for x <= 0.
std::vector<ModelPtr> twoWalls() {
  return {std::make_shared<const CollisionModel>(
      ModelMaker().addBox({{0, -40, -50}, {100, -10, 100}}).addBox({{-100, 14, -50}, {0, 40, 100}}).build())};
}

constexpr const char* kBar = "contacts trm=box:-30,-2,0,30,2,16 start=0,0,0 max=64";
constexpr const char* kTurn = " rotorigin=0,0,0 rotaxis=0,0,1 angle=30";

// The angle at which a bar corner (30, 2 from the axis) gets within the clip
// epsilon of a wall `d` from the axis (as the C++ test computes it).
double cornerAngle(double d) {
  const double r = std::sqrt(30.0 * 30 + 2 * 2);
  return (std::asin((d - double(tol::kClipEpsilon)) / r) - std::atan(2.0 / 30)) * 180 / std::numbers::pi;
}

// The value of `key=` in a result line, as a float ("" when absent).
std::string field(const std::string& line, const std::string& key) {
  const std::size_t at = line.find(" " + key + "=");
  if (at == std::string::npos) return {};
  const std::size_t begin = at + key.size() + 2;
  return line.substr(begin, line.find(' ', begin) - begin);
}

std::string answer(const std::vector<ModelPtr>& models, const std::string& line) {
  QueryWork work;
  return answerQueryLine(models, line, work);
}

}  // namespace

TEST(QueryFormatRotationContacts, BarIntoTwoWallsGivesEachContactsAngle) {
  const auto models = twoWalls();
  const std::string line = std::string(kBar) + kTurn;
  const std::string result = answer(models, line);
  ASSERT_EQ(result.rfind("count=2 type.0=trmvertex ", 0), 0u) << result;
  // The +x end meets y = -10 first, then the -x end y = 14.
  EXPECT_NEAR(std::strtod(field(result, "angle.0").c_str(), nullptr), cornerAngle(10), 1e-3) << result;
  EXPECT_NEAR(std::strtod(field(result, "angle.1").c_str(), nullptr), cornerAngle(14), 1e-3) << result;
  EXPECT_EQ(field(result, "normal.0"), "0,1,0");
  EXPECT_EQ(field(result, "normal.1"), "0,-1,0");
  // angle.i= follows trmfeature.i=, the last of the other contact fields.
  EXPECT_NE(result.find(" trmfeature.0=" + field(result, "trmfeature.0") + " angle.0="), std::string::npos);

  // The same contacts, in the same order, as the C++ API's, each angle
  // printed with %.9g (which gives back the float).
  const TraceModel bar = *TraceModel::box({{-30, -2, 0}, {30, 2, 16}});
  ContactsQuery q;
  q.trm = &bar;
  q.maxContacts = 64;
  q.rotation = Rotation({0, 0, 0}, {0, 0, 1}, 30);
  QueryWork work;
  const ContactsResult direct = contacts(*models[0], q, work);
  ASSERT_EQ(direct.contacts.size(), 2u);
  for (int i = 0; i < 2; ++i)
    expectPrintedAs(Real(std::strtod(field(result, "angle." + std::to_string(i)).c_str(), nullptr)),
                    direct.contacts[std::size_t(i)].angle);

  // Turning the other way meets nothing.
  EXPECT_EQ(answer(models, std::string(kBar) + " rotorigin=0,0,0 rotaxis=0,0,1 angle=-30"), "count=0");
}

TEST(QueryFormatRotationContacts, DirAndDepthMayBeLeftOutOrZero) {
  const auto models = twoWalls();
  const std::string expected = answer(models, std::string(kBar) + kTurn);
  EXPECT_EQ(answer(models, std::string(kBar) + kTurn + " dir=0,0,0 depth=0"), expected);
  EXPECT_EQ(answer(models, std::string(kBar) + kTurn + " dir=0,0,1"), expected);  // no depth: 0
  EXPECT_EQ(answer(models, std::string(kBar) + kTurn + " depth=8"), expected);    // no dir: 0
  EXPECT_EQ(answer(models, std::string(kBar) + kTurn + " dir=0,0,0 depth=8"), expected);
  // Both a translation and a rotation: refused, and the line says why.
  EXPECT_EQ(answer(models, std::string(kBar) + kTurn + " dir=1,0,0 depth=8"),
            "error=refused: contacts query given both a translation (dir and depth) and a rotation");
}

TEST(QueryFormatRotationContacts, RotationKeysAreThoseOfRotationLines) {
  const auto models = twoWalls();
  const std::string bar = kBar;
  EXPECT_EQ(answer(models, bar + " rotorigin=0,0,0 angle=30"), "error=missing rotaxis");
  EXPECT_EQ(answer(models, bar + " rotaxis=0,0,1 angle=30"), "error=missing rotorigin");
  EXPECT_EQ(answer(models, bar + " rotorigin=0,0,0 rotaxis=0,0,1"), "error=missing angle");
  EXPECT_EQ(answer(models, bar + " rotorigin=0,0,0 rotaxis=0,0,2 angle=30"), "error=rotaxis not unit length");
  EXPECT_EQ(answer(models, bar + " rotorigin=0,0,0 rotaxis=0,0,1 angle=x"), "error=bad number in angle");
  // Without them a contacts line needs its translation, as before.
  EXPECT_EQ(answer(models, bar), "error=missing dir");
  EXPECT_EQ(answer(models, bar + " dir=0,1,0"), "error=missing depth");
}

TEST(QueryFormatRotationContacts, TranslationContactsHaveNoAngleField) {
  const auto models = twoWalls();
  const std::string line = "contacts trm=box:-30,-2,0,30,2,16 start=0,-7,0 dir=0,-1,0 depth=8";
  const auto parsed = parseQueryLine(models, line);
  ASSERT_TRUE(parsed.ok());
  EXPECT_FALSE(parsed->rotational);
  const std::string result = answer(models, line);
  ASSERT_EQ(result.rfind("count=", 0), 0u) << result;
  ASSERT_NE(result.rfind("count=0", 0), 0u) << "the bar is 1 unit from the wall: " << result;
  EXPECT_EQ(result.find("angle"), std::string::npos) << result;
}

TEST(QueryFormatRotationContacts, ResultLineReadsBackAsTheContacts) {
  const auto models = twoWalls();
  const std::string line = std::string(kBar) + kTurn;
  const auto parsed = parseQueryLine(models, line);
  ASSERT_TRUE(parsed.ok());
  EXPECT_TRUE(parsed->rotational);
  QueryWork work;
  std::vector<ContactInfo> found;
  ASSERT_EQ(runParsedQueryUnformatted(models, *parsed, work, found), 2.0);
  const std::string result = runParsedQuery(models, *parsed, work);
  const auto records = parseTraceRecords(line, result);
  ASSERT_EQ(records.size(), 1u);
  ASSERT_TRUE(records[0].error.empty()) << records[0].error;
  // The reader shows the first contact: every field as written, the angle too.
  const ContactInfo& read = records[0].result.contact;
  const ContactInfo& first = found[0];
  EXPECT_EQ(read.type, first.type);
  for (int k = 0; k < 3; ++k) {
    expectPrintedAs(read.point[k], first.point[k]);
    expectPrintedAs(read.normal[k], first.normal[k]);
  }
  expectPrintedAs(read.dist, first.dist);
  EXPECT_EQ(read.contents, first.contents);
  EXPECT_EQ(read.modelFeature, first.modelFeature);
  EXPECT_EQ(read.trmFeature, first.trmFeature);
  expectPrintedAs(read.angle, first.angle);
  EXPECT_NE(read.angle, 0);
}
