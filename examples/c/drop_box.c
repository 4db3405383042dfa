/* drop_box.c: cmkit's C API in a few calls (include/cmkit/cmkit.h).
 *
 * Loads a map's world (default: tests/data/maps/two_halls.map, two halls
 * joined by a doorway that a func_door named door1 fills), drops a player
 * box onto the floor, walks it into the closed door, opens the door by
 * moving its entity up and walks again; then a player walks through.
 *
 *   drop_box [MAP]
 */
#include <stdio.h>

#include <cmkit/cmkit.h>

#ifndef CMKIT_EXAMPLE_C_MAP /* the build names the source tree's map */
#define CMKIT_EXAMPLE_C_MAP "tests/data/maps/two_halls.map"
#endif

static int check(cmkit_status status, const char* what) {
  if (status != CMKIT_OK) fprintf(stderr, "%s: %s\n", what, cmkit_last_error());
  return status == CMKIT_OK;
}

int main(int argc, char** argv) {
  const char* path = argc > 1 ? argv[1] : CMKIT_EXAMPLE_C_MAP;
  cmkit_world_t* world = NULL;
  cmkit_trace_model_t* player = NULL;
  int ok = check(cmkit_load_map(path, &world), "cmkit_load_map") &&
           check(cmkit_trace_model_box(-16, -16, 0, 16, 16, 74, &player), "cmkit_trace_model_box");
  if (ok) {
    /* Dropped from 40 units above the floor (z = 0; the box is 74 high and
     * the ceiling at 128): it stops 0.25 units above the floor, after
     * (40 - 0.25) / 100 of the move. */
    const float top[3] = {-200, 0, 40}, below[3] = {-200, 0, -60};
    cmkit_trace_t trace;
    ok = check(cmkit_translate(world, player, NULL, top, below, CMKIT_MASK_PLAYER_SOLID, &trace), "drop");
    if (ok)
      printf("dropped: fraction %.5f, end z %.2f, normal %.0f %.0f %.0f, entity %s\n", trace.fraction,
             trace.end[2], trace.normal[0], trace.normal[1], trace.normal[2],
             cmkit_world_entity_name(world, trace.entity));

    /* Walk through the doorway: the closed door stops the box. */
    const float from[3] = {-200, 0, 1}, to[3] = {200, 0, 1};
    ok = ok && check(cmkit_translate(world, player, NULL, from, to, CMKIT_MASK_PLAYER_SOLID, &trace), "walk");
    if (ok)
      printf("closed door: fraction %.6f, end x %.2f, entity %s\n", trace.fraction, trace.end[0],
             trace.entity == CMKIT_NO_ENTITY ? "(none)" : cmkit_world_entity_name(world, trace.entity));

    /* Open it (move its entity 128 units up) and walk again. */
    cmkit_entity_t door = CMKIT_NO_ENTITY;
    float origin[3];
    ok = ok && check(cmkit_world_find_entity(world, "door1", &door), "find door1") &&
         check(cmkit_world_get_placement(world, door, origin, NULL), "placement");
    if (ok) {
      origin[2] += 128;
      ok = check(cmkit_world_set_placement(world, door, origin, NULL), "open the door") &&
           check(cmkit_translate(world, player, NULL, from, to, CMKIT_MASK_PLAYER_SOLID, &trace),
                 "walk again");
      if (ok)
        printf("open door: fraction %.6f, end x %.2f, entity %s\n", trace.fraction, trace.end[0],
               trace.entity == CMKIT_NO_ENTITY ? "(none)" : cmkit_world_entity_name(world, trace.entity));
    }

    /* A player (the engine's box, gravity, steps) walks 3 seconds along +x
     * through the open doorway. */
    cmkit_player_t* walker = NULL;
    const float feet[3] = {-200, 0, 1}, east[3] = {1, 0, 0};
    cmkit_player_state_t state;
    ok = ok && check(cmkit_player_create(NULL, feet, &walker), "cmkit_player_create") &&
         check(cmkit_player_step(world, walker, east, 0, 180, &state), "cmkit_player_step");
    if (ok)
      printf("player: end %.2f %.2f %.2f after %lld steps, %s\n", state.origin[0], state.origin[1], state.origin[2],
             (long long)state.steps, state.on_ground ? "on the ground" : "in the air");
    cmkit_player_free(walker);
  }
  cmkit_trace_model_free(player);
  cmkit_world_free(world);
  return ok ? 0 : 1;
}
