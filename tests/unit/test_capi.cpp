// The C API (cmkit/cmkit.h): its answers are the C++ World's, its errors are
// status codes with a message of the calling thread, its batches equal loops
// of single calls at any thread count. (The header as C11 with warnings as
// errors: examples/c/drop_box.c, built by every build and by the consumer
// test through pkg-config --static.)
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "cmkit/cmkit.h"
#include "cmkit/movement.h"
#include "cmkit/version.h"
#include "cmkit/world.h"
#include "test_support.h"

using namespace cmkit;

namespace {

std::string twoHalls() { return (test::testDataDir() / "maps" / "two_halls.map").string(); }

// Owns a C world and a player box.
struct CWorld {
  cmkit_world_t* world = nullptr;
  cmkit_trace_model_t* box = nullptr;
  CWorld() {
    EXPECT_EQ(cmkit_load_map(twoHalls().c_str(), &world), CMKIT_OK) << cmkit_last_error();
    EXPECT_EQ(cmkit_trace_model_box(-16, -16, 0, 16, 16, 74, &box), CMKIT_OK) << cmkit_last_error();
  }
  ~CWorld() {
    cmkit_trace_model_free(box);
    cmkit_world_free(world);
  }
  CWorld(const CWorld&) = delete;
  CWorld& operator=(const CWorld&) = delete;
};

}  // namespace

TEST(CApi, VersionAndContentFlagsAreTheLibrarys) {
  EXPECT_STREQ(cmkit_version(), CMKIT_VERSION_STRING);
  EXPECT_EQ(CMKIT_CONTENTS_SOLID, contents::kSolid);
  EXPECT_EQ(CMKIT_CONTENTS_PLAYERCLIP, contents::kPlayerClip);
  EXPECT_EQ(CMKIT_CONTENTS_TRIGGER, contents::kTrigger);
  EXPECT_EQ(CMKIT_CONTENTS_FLASHLIGHT_TRIGGER, contents::kFlashlightTrigger);
  EXPECT_EQ(CMKIT_MASK_PLAYER_SOLID, contents::kMaskPlayerSolid);
  EXPECT_EQ(CMKIT_MASK_MONSTER_SOLID, contents::kMaskMonsterSolid);
  EXPECT_EQ(CMKIT_MASK_ALL, contents::kMaskAll);
  EXPECT_EQ(int(CMKIT_CONTACT_EDGE), int(ContactType::Edge));
  EXPECT_EQ(int(CMKIT_CONTACT_MODEL_VERTEX), int(ContactType::ModelVertex));
  EXPECT_EQ(int(CMKIT_CONTACT_TRM_VERTEX), int(ContactType::TrmVertex));
}

TEST(CApi, ErrorsAreStatusesWithAMessageOfTheCallingThread) {
  cmkit_world_t* world = nullptr;
  EXPECT_EQ(cmkit_load_map(nullptr, &world), CMKIT_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(cmkit_last_error()).find("path is NULL"), std::string::npos) << cmkit_last_error();
  EXPECT_EQ(cmkit_load_map("/nonexistent/cmkit/none.map", &world), CMKIT_ERROR_FILE);
  EXPECT_NE(std::string(cmkit_last_error()).find("none.map"), std::string::npos) << cmkit_last_error();
  EXPECT_EQ(world, nullptr);

  // A map with a syntax error: file and line in the message.
  const test::ScratchDir dir("capi_bad_map");
  const std::string bad = (dir.path() / "bad.map").string();
  std::ofstream(bad) << "Version 2\n{\n\"classname\" \"worldspawn\"\n{\n brushDef3\n {\n  ( 0 0 1\n";
  EXPECT_EQ(cmkit_load_map(bad.c_str(), &world), CMKIT_ERROR_FILE);
  EXPECT_NE(std::string(cmkit_last_error()).find("bad.map:"), std::string::npos) << cmkit_last_error();

  cmkit_trace_model_t* trm = nullptr;
  EXPECT_EQ(cmkit_trace_model_from_spec("box:1,2", &trm), CMKIT_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(trm, nullptr);
  EXPECT_EQ(cmkit_trace_model_box(16, 16, 16, -16, -16, -16, &trm), CMKIT_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(cmkit_trace_model_cylinder(-8, -8, 0, 8, 8, 64, 2, &trm), CMKIT_ERROR_INVALID_ARGUMENT);

  // Another thread's errors are its own.
  const std::string mine = cmkit_last_error();
  std::string theirs;
  std::thread([&] {
    EXPECT_STREQ(cmkit_last_error(), "");
    cmkit_world_t* w = nullptr;
    EXPECT_EQ(cmkit_load_map("/nonexistent/other.map", &w), CMKIT_ERROR_FILE);
    theirs = cmkit_last_error();
  }).join();
  EXPECT_EQ(cmkit_last_error(), mine);
  EXPECT_NE(theirs.find("other.map"), std::string::npos);

  CWorld w;
  cmkit_entity_t id = 0;
  EXPECT_EQ(cmkit_world_find_entity(w.world, "no_such_door", &id), CMKIT_ERROR_NOT_FOUND);
  EXPECT_EQ(cmkit_world_entity_name(w.world, 12345), nullptr);
  const float origin[3] = {0, 0, 0};
  EXPECT_EQ(cmkit_world_set_placement(w.world, 12345, origin, nullptr), CMKIT_ERROR_NOT_FOUND);
  const float sheared[9] = {1, 0, 0, 0.5f, 1, 0, 0, 0, 1};
  EXPECT_EQ(cmkit_world_set_placement(w.world, 0, origin, sheared), CMKIT_ERROR_INVALID_ARGUMENT);

  // A refused query: a status, and the trace written as refused.
  cmkit_trace_t t;
  const float nan3[3] = {std::nanf(""), 0, 0};
  EXPECT_EQ(cmkit_translate(w.world, w.box, nullptr, nan3, origin, CMKIT_MASK_SOLID, &t),
            CMKIT_ERROR_REFUSED);
  EXPECT_EQ(t.fraction, 0.0f);
  EXPECT_NE(std::string(cmkit_last_error()).find("refused"), std::string::npos);
  EXPECT_EQ(cmkit_translate(w.world, w.box, nullptr, origin, origin, CMKIT_MASK_SOLID, nullptr),
            CMKIT_ERROR_INVALID_ARGUMENT);
  cmkit_world_free(nullptr);
  cmkit_trace_model_free(nullptr);
}

TEST(CApi, TheDoorStopsTheBoxUntilItMoves) {
  CWorld w;
  // Dropped from 40 above the floor (z = 0; the ceiling is at 128): stops 0.25 above it.
  const float top[3] = {-200, 0, 40}, below[3] = {-200, 0, -60};
  cmkit_trace_t t;
  ASSERT_EQ(cmkit_translate(w.world, w.box, nullptr, top, below, CMKIT_MASK_PLAYER_SOLID, &t), CMKIT_OK);
  EXPECT_FLOAT_EQ(t.fraction, (40.0f - 0.25f) / 100.0f);
  EXPECT_FLOAT_EQ(t.end[2], 0.25f);
  EXPECT_EQ(t.normal[2], 1.0f);
  EXPECT_EQ(t.entity, 0);
  EXPECT_STREQ(cmkit_world_entity_name(w.world, t.entity), "worldspawn");
  EXPECT_EQ(t.start_solid, 0);

  // Through the doorway: the door (world x -4..4) stops the box's face at x = -4 - 16 - 0.25.
  const float from[3] = {-200, 0, 1}, to[3] = {200, 0, 1};
  ASSERT_EQ(cmkit_translate(w.world, w.box, nullptr, from, to, CMKIT_MASK_PLAYER_SOLID, &t), CMKIT_OK);
  EXPECT_FLOAT_EQ(t.end[0], -20.25f);
  EXPECT_STREQ(cmkit_world_entity_name(w.world, t.entity), "door1");
  EXPECT_EQ(t.normal[0], -1.0f);

  cmkit_entity_t door = CMKIT_NO_ENTITY;
  ASSERT_EQ(cmkit_world_find_entity(w.world, "door1", &door), CMKIT_OK);
  float origin[3], axis[9];
  ASSERT_EQ(cmkit_world_get_placement(w.world, door, origin, axis), CMKIT_OK);
  EXPECT_EQ(origin[2], 48.0f);  // the map's "origin" "0 0 48"
  origin[2] += 128;
  ASSERT_EQ(cmkit_world_set_placement(w.world, door, origin, axis), CMKIT_OK);
  ASSERT_EQ(cmkit_translate(w.world, w.box, nullptr, from, to, CMKIT_MASK_PLAYER_SOLID, &t), CMKIT_OK);
  EXPECT_EQ(t.fraction, 1.0f);
  EXPECT_EQ(t.entity, CMKIT_NO_ENTITY);

  // Back down, but not solid any more: it passes too.
  origin[2] -= 128;
  ASSERT_EQ(cmkit_world_set_placement(w.world, door, origin, axis), CMKIT_OK);
  ASSERT_EQ(cmkit_world_set_contents(w.world, door, 0), CMKIT_OK);
  ASSERT_EQ(cmkit_translate(w.world, w.box, nullptr, from, to, CMKIT_MASK_PLAYER_SOLID, &t), CMKIT_OK);
  EXPECT_EQ(t.fraction, 1.0f);
}

TEST(CApi, AnswersAreTheWorldsBitForBit) {
  CWorld w;
  Result<LoadedWorld> loaded = World::loadMap(twoHalls(), MaterialTable{});
  ASSERT_TRUE(loaded) << loaded.error().toString();
  const World& world = loaded->world;
  Result<TraceModel> box = TraceModel::box({{-16, -16, 0}, {16, 16, 74}});
  ASSERT_TRUE(box);
  WorldQueryWork work;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> x(-500, 500), y(-120, 120), z(-10, 140);
  for (int i = 0; i < 300; ++i) {
    const float start[3] = {x(rng), y(rng), z(rng)}, end[3] = {x(rng), y(rng), z(rng)};
    TranslationQuery q;
    q.trm = &*box;
    q.start = Vec3(start[0], start[1], start[2]);
    q.end = Vec3(end[0], end[1], end[2]);
    q.contentMask = contents::kMaskPlayerSolid;
    q.detectStartSolid = true;
    const WorldTraceResult expected = world.translate(q, work);
    cmkit_trace_t t;
    ASSERT_EQ(cmkit_translate(w.world, w.box, nullptr, start, end, CMKIT_MASK_PLAYER_SOLID, &t), CMKIT_OK);
    EXPECT_EQ(t.fraction, float(expected.trace.fraction));
    EXPECT_EQ(t.end[0], float(expected.trace.endPos.x));
    EXPECT_EQ(t.end[2], float(expected.trace.endPos.z));
    EXPECT_EQ(t.normal[0], float(expected.trace.contact.normal.x));
    EXPECT_EQ(t.entity, expected.entity);
    EXPECT_EQ(t.start_solid, expected.trace.startSolid ? 1 : 0);

    uint32_t c = 0;
    cmkit_entity_t e = 0;
    ASSERT_EQ(cmkit_point_contents(w.world, start, &c, &e), CMKIT_OK);
    PointContentsQuery pq;
    pq.point = q.start;
    const WorldPointContentsResult pc = world.pointContents(pq, work);
    EXPECT_EQ(c, pc.contents);
    EXPECT_EQ(e, pc.entity);

    cmkit_ray_hit_t hit;
    ASSERT_EQ(cmkit_cast_ray(w.world, start, end, CMKIT_MASK_SOLID, &hit), CMKIT_OK);
    RayCastQuery rq;
    rq.start = q.start;
    rq.end = q.end;
    const WorldRayHit rh = world.castRay(rq, work);
    EXPECT_EQ(hit.fraction, float(rh.hit.fraction));
    EXPECT_EQ(hit.entity, rh.entity);

    std::array<cmkit_contact_t, 8> contacts{};
    int32_t count = -1;
    const float dir[3] = {end[0] - start[0], end[1] - start[1], end[2] - start[2]};
    ASSERT_EQ(cmkit_contacts(w.world, w.box, nullptr, start, dir, 1.0f, CMKIT_MASK_SOLID, contacts.data(), 8,
                             &count),
              CMKIT_OK);
    ContactsQuery cq;
    cq.trm = &*box;
    cq.start = q.start;
    cq.dir = Vec3(dir[0], dir[1], dir[2]);
    cq.depth = 1;
    cq.maxContacts = 8;
    const WorldContactsResult cr = world.contacts(cq, work);
    ASSERT_EQ(count, int32_t(cr.contacts.size()));
    for (int32_t k = 0; k < count; ++k) {
      EXPECT_EQ(contacts[size_t(k)].entity, cr.contacts[size_t(k)].entity);
      EXPECT_EQ(contacts[size_t(k)].point[0], float(cr.contacts[size_t(k)].contact.point.x));
    }
  }
}

TEST(CApi, BatchesEqualSingleCallsAtAnyThreadCount) {
  CWorld w;
  constexpr size_t n = 500;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> x(-500, 500), y(-120, 120), z(-10, 140);
  std::vector<float> starts(3 * n), ends(3 * n);
  for (size_t i = 0; i < 3 * n; i += 3) {
    starts[i] = x(rng), starts[i + 1] = y(rng), starts[i + 2] = z(rng);
    ends[i] = x(rng), ends[i + 1] = y(rng), ends[i + 2] = z(rng);
  }
  std::vector<cmkit_trace_t> single(n);
  std::vector<uint32_t> singleContents(n);
  std::vector<cmkit_ray_hit_t> singleRays(n);
  for (size_t i = 0; i < n; ++i) {
    // A refused query is a status of the single call, not of the batch.
    (void)cmkit_translate(w.world, w.box, nullptr, &starts[3 * i], &ends[3 * i], CMKIT_MASK_PLAYER_SOLID,
                          &single[i]);
    ASSERT_EQ(cmkit_point_contents(w.world, &starts[3 * i], &singleContents[i], nullptr), CMKIT_OK);
    ASSERT_EQ(cmkit_cast_ray(w.world, &starts[3 * i], &ends[3 * i], CMKIT_MASK_SOLID, &singleRays[i]),
              CMKIT_OK);
  }
  for (int threads : {1, 3}) {
    std::vector<cmkit_trace_t> batch(n);
    ASSERT_EQ(cmkit_translate_batch(w.world, w.box, nullptr, starts.data(), ends.data(), n,
                                    CMKIT_MASK_PLAYER_SOLID, threads, batch.data()),
              CMKIT_OK)
        << cmkit_last_error();
    EXPECT_EQ(std::memcmp(batch.data(), single.data(), n * sizeof(cmkit_trace_t)), 0)
        << threads << " threads";
    std::vector<uint32_t> c(n);
    std::vector<cmkit_entity_t> e(n);
    ASSERT_EQ(cmkit_point_contents_batch(w.world, starts.data(), n, threads, c.data(), e.data()), CMKIT_OK);
    EXPECT_EQ(c, singleContents);
    std::vector<cmkit_ray_hit_t> rays(n);
    ASSERT_EQ(
        cmkit_cast_ray_batch(w.world, starts.data(), ends.data(), n, CMKIT_MASK_SOLID, threads, rays.data()),
        CMKIT_OK);
    EXPECT_EQ(std::memcmp(rays.data(), singleRays.data(), n * sizeof(cmkit_ray_hit_t)), 0) << threads;
  }
  EXPECT_EQ(cmkit_translate_batch(w.world, w.box, nullptr, nullptr, nullptr, 0, CMKIT_MASK_SOLID, 1, nullptr),
            CMKIT_OK);
  EXPECT_EQ(cmkit_translate_batch(w.world, w.box, nullptr, nullptr, ends.data(), n, CMKIT_MASK_SOLID, 1,
                                  single.data()),
            CMKIT_ERROR_INVALID_ARGUMENT);
}

TEST(CApi, PlayerClimbsTheStairsAsTheLibrarysMoveDoes) {
  const std::string stairs = (test::testDataDir() / "maps" / "stairs.map").string();
  cmkit_world_t* world = nullptr;
  ASSERT_EQ(cmkit_load_map(stairs.c_str(), &world), CMKIT_OK) << cmkit_last_error();
  cmkit_player_t* player = nullptr;
  const float feet[3] = {-64, 64, 1}, east[3] = {1, 0, 0};
  ASSERT_EQ(cmkit_player_create(nullptr, feet, &player), CMKIT_OK);
  cmkit_player_state_t state;
  // Two calls of 120 steps are one run of 240.
  ASSERT_EQ(cmkit_player_step(world, player, east, 0, 120, nullptr), CMKIT_OK);
  ASSERT_EQ(cmkit_player_step(world, player, east, 0, 120, &state), CMKIT_OK);
  EXPECT_EQ(state.steps, 240);
  EXPECT_NEAR(state.origin[0], 239.75f, 0.05f);  // on the landing (tests/unit/test_movement.cpp)
  EXPECT_NEAR(state.origin[2], 60.25f, 0.05f);
  EXPECT_EQ(state.on_ground, 1);
  EXPECT_EQ(state.ground_entity, 0);

  Result<LoadedWorld> loaded = World::loadMap(stairs, MaterialTable{});
  ASSERT_TRUE(loaded);
  WorldQueryWork work;
  PlayerState start;
  start.origin = Vec3(-64, 64, 1);
  PlayerInput input;
  input.wishDir = Vec3(1, 0, 0);
  const PlayerState expected =
      runPlayer(loaded->world, PlayerShape::standard(), start, input, 240, move::kTimeStep, work);
  EXPECT_EQ(state.origin[0], float(expected.origin.x));
  EXPECT_EQ(state.origin[2], float(expected.origin.z));
  EXPECT_EQ(state.velocity[0], float(expected.velocity.x));

  // Held by the 24-unit risers; a teleport starts at rest.
  const float held[3] = {-64, -64, 1};
  ASSERT_EQ(cmkit_player_set_origin(player, held), CMKIT_OK);
  ASSERT_EQ(cmkit_player_step(world, player, east, CMKIT_PLAYER_RUN, 240, &state), CMKIT_OK);
  EXPECT_NEAR(state.origin[0], 47.75f, 0.05f);
  EXPECT_NEAR(state.origin[2], 0.25f, 0.05f);
  EXPECT_EQ(cmkit_player_step(world, player, east, 0, -1, &state), CMKIT_ERROR_INVALID_ARGUMENT);
  cmkit_trace_model_t* point = nullptr;
  ASSERT_EQ(cmkit_trace_model_from_spec("point", &point), CMKIT_OK);
  cmkit_player_t* bad = nullptr;
  EXPECT_EQ(cmkit_player_create(point, feet, &bad), CMKIT_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bad, nullptr);
  cmkit_trace_model_free(point);
  cmkit_player_free(player);
  cmkit_world_free(world);
}

// One writer, many readers (cmkit.h, THREAD SAFETY): four threads query the
// world and step players of their own at once (translations, position tests,
// rays, a batch, player steps), then the one writer moves and disables the
// door between the rounds, never while they run. Every reader's answers
// equal, bit for bit, one thread's made before the round. (Run under
// ThreadSanitizer by ./dev.sh tsan: no race.)
TEST(CApi, ReadersOnManyThreadsBetweenTheWritersChanges) {
  CWorld w;
  cmkit_entity_t door = CMKIT_NO_ENTITY;
  ASSERT_EQ(cmkit_world_find_entity(w.world, "door1", &door), CMKIT_OK);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> x(-220, 220), y(-40, 40), z(1, 40);
  constexpr std::size_t n = 64;
  std::vector<std::array<float, 3>> from(n), to(n);
  for (std::size_t i = 0; i < n; ++i) {
    from[i] = {x(rng), y(rng), z(rng)};
    to[i] = {x(rng), y(rng), z(rng)};
  }
  // What one reader does: every query, then a player's walk through the
  // doorway; its answers as bytes.
  auto read = [&](std::vector<unsigned char>& out) {
    out.clear();
    auto keep = [&out](const void* p, std::size_t size) {
      const auto* b = static_cast<const unsigned char*>(p);
      out.insert(out.end(), b, b + size);
    };
    for (std::size_t i = 0; i < n; ++i) {
      cmkit_trace_t t{};
      EXPECT_EQ(
          cmkit_translate(w.world, w.box, nullptr, from[i].data(), to[i].data(), CMKIT_MASK_PLAYER_SOLID, &t),
          CMKIT_OK);
      keep(&t, sizeof t);
      std::uint32_t contents = 0;
      cmkit_entity_t entity = CMKIT_NO_ENTITY;
      EXPECT_EQ(
          cmkit_contents(w.world, w.box, nullptr, to[i].data(), CMKIT_MASK_PLAYER_SOLID, &contents, &entity),
          CMKIT_OK);
      keep(&contents, sizeof contents);
      keep(&entity, sizeof entity);
      cmkit_ray_hit_t r{};
      EXPECT_EQ(cmkit_cast_ray(w.world, from[i].data(), to[i].data(), CMKIT_MASK_SOLID, &r), CMKIT_OK);
      keep(&r, sizeof r);
    }
    std::vector<cmkit_trace_t> batch(n, cmkit_trace_t{});
    EXPECT_EQ(cmkit_translate_batch(w.world, w.box, nullptr, from.data()->data(), to.data()->data(), n,
                                    CMKIT_MASK_PLAYER_SOLID, 2, batch.data()),
              CMKIT_OK);
    keep(batch.data(), n * sizeof(cmkit_trace_t));
    cmkit_player_t* player = nullptr;
    const float feet[3] = {-150, 0, 1}, east[3] = {1, 0, 0};
    EXPECT_EQ(cmkit_player_create(nullptr, feet, &player), CMKIT_OK);
    cmkit_player_state_t state{};
    EXPECT_EQ(cmkit_player_step(w.world, player, east, CMKIT_PLAYER_RUN, 90, &state), CMKIT_OK);
    keep(&state, sizeof state);
    cmkit_player_free(player);
  };
  float origin[3], axis[9];
  ASSERT_EQ(cmkit_world_get_placement(w.world, door, origin, axis), CMKIT_OK);
  std::vector<unsigned char> first;
  for (int round = 0; round < 3; ++round) {
    std::vector<unsigned char> expected;
    read(expected);
    if (round == 0)
      first = expected;
    else
      EXPECT_NE(expected, first) << "round " << round << ": the door still stops the same moves";
    std::array<std::vector<unsigned char>, 4> got;
    std::vector<std::thread> readers;
    for (std::size_t t = 0; t < got.size(); ++t) readers.emplace_back([&, t] { read(got[t]); });
    for (std::thread& r : readers) r.join();
    for (std::size_t t = 0; t < got.size(); ++t)
      EXPECT_EQ(got[t], expected) << "round " << round << " reader " << t;
    // The one writer, between the rounds: the door up, then down again but
    // not solid.
    if (round == 0) {
      origin[2] += 128;
      ASSERT_EQ(cmkit_world_set_placement(w.world, door, origin, axis), CMKIT_OK);
    } else if (round == 1) {
      origin[2] -= 128;
      ASSERT_EQ(cmkit_world_set_placement(w.world, door, origin, axis), CMKIT_OK);
      ASSERT_EQ(cmkit_world_set_contents(w.world, door, 0), CMKIT_OK);
    }
  }
}
