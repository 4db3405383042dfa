// contacts() (src/query/contacts.cpp): every surface a trace model meets
// along a move, in world space; the form that fills the caller's vector.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "cmkit/query.h"
#include "model_fixtures.h"

using namespace cmkit;
using cmkit::test::ModelMaker;

namespace {

// A floor (top at z = 0) and a wall (x from 20 to 40), for the contacts tests.
CollisionModel floorAndWall() {
  return ModelMaker()
      .addBox({{-100, -100, -16}, {100, 100, 0}})
      .addBox({{20, -100, 0}, {40, 100, 100}})
      .build();
}

/// A contacts query of `trm` collecting up to 32 contacts (start, direction
/// and depth for the test to set).
ContactsQuery contactsOf(const TraceModel& trm) {
  ContactsQuery q;
  q.trm = &trm;
  q.maxContacts = 32;
  return q;
}

}  // namespace

TEST(Contacts, AllSurfacesAlongTheMove) {
  // A box in the corner of the floor and the wall; moving down and into +x.
  const CollisionModel m = floorAndWall();
  const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 32}});
  QueryWork work;
  ContactsQuery q = contactsOf(box);
  q.start = {3.9f, 0, 0.1f};
  q.dir = {1, 0, -1};
  q.depth = 1;
  const std::vector<ContactInfo> found = contacts(m, q, work).contacts;
  ASSERT_FALSE(found.empty());
  bool floor = false, wall = false;
  for (const ContactInfo& c : found) {
    floor |= c.normal == Vec3(0, 0, 1);
    wall |= c.normal == Vec3(-1, 0, 0);
  }
  EXPECT_TRUE(floor);
  EXPECT_TRUE(wall);
  q.maxContacts = 1;
  EXPECT_EQ(contacts(m, q, work).contacts.size(), 1u);
  q.depth = 0;
  EXPECT_TRUE(contacts(m, q, work).contacts.empty());
}

TEST(Contacts, IntoTheCallersVectorGivesTheSameContacts) {
  // contacts(..., out) gives what contacts() returns, contact for contact,
  // whatever `out` held before; a refused query leaves it empty.
  const CollisionModel m = floorAndWall();
  const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 32}});
  QueryWork work;
  ContactsQuery q = contactsOf(box);
  std::vector<ContactInfo> out(5);  // stale entries: must be cleared
  int withContacts = 0;
  for (int k = 0; k < 40; ++k) {
    q.start = {Real(-4 + k * 0.25), Real(k % 7), Real(0.1 + (k % 3) * 0.5)};
    q.dir = {Real(1 - (k % 2)), Real(k % 3 - 1), -1};
    q.depth = Real(1 + k % 4);
    const ContactsResult byValue = contacts(m, q, work);
    ASSERT_EQ(contacts(m, q, work, out), byValue.status);
    ASSERT_EQ(out.size(), byValue.contacts.size()) << "query " << k;
    withContacts += !out.empty();
    for (std::size_t i = 0; i < out.size(); ++i) {
      EXPECT_EQ(out[i].normal, byValue.contacts[i].normal);
      EXPECT_EQ(out[i].point, byValue.contacts[i].point);
      EXPECT_EQ(out[i].dist, byValue.contacts[i].dist);
      EXPECT_EQ(out[i].type, byValue.contacts[i].type);
      EXPECT_EQ(out[i].modelFeature, byValue.contacts[i].modelFeature);
      EXPECT_EQ(out[i].trmFeature, byValue.contacts[i].trmFeature);
    }
  }
  EXPECT_GT(withContacts, 10);  // the moves do touch the floor and the wall
  q.depth = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_EQ(contacts(m, q, work, out), QueryStatus::NonFinite);
  EXPECT_TRUE(out.empty());
}
