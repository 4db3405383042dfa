// The C API's player (include/cmkit/cmkit.h): a PlayerShape and its
// PlayerState behind a handle, stepped with runPlayer.
#include <string>
#include <utility>

#include "capi/capi_support.h"

namespace {

using cmkit::Real;
using cmkit::Vec3;
using namespace cmkit::detail::capi;

void fillPlayer(const cmkit::PlayerState& state, cmkit_player_state_t* out) {
  *out = cmkit_player_state_t{};
  put(out->origin, state.origin);
  put(out->velocity, state.velocity);
  put(out->ground_normal, state.groundNormal);
  out->ground_entity = state.groundEntity;
  out->on_ground = state.onGround ? 1 : 0;
  out->crouched = state.crouched ? 1 : 0;
  out->stuck = state.stuck ? 1 : 0;
  out->steps = state.steps;
}

}  // namespace

extern "C" {

cmkit_status cmkit_player_create(const cmkit_trace_model_t* shape, const float origin[3],
                                 cmkit_player_t** out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(origin);
    CMKIT_REQUIRE(out);
    cmkit::PlayerShape playerShape = cmkit::PlayerShape::standard();
    if (shape != nullptr) {
      cmkit::Result<cmkit::PlayerShape> made = cmkit::PlayerShape::fromTraceModel(shape->trm);
      if (!made) return failWith(made.error());
      playerShape = std::move(*made);
    }
    cmkit::PlayerState state;
    state.origin = vec(origin);
    *out = new cmkit_player{std::move(playerShape), state};
    return CMKIT_OK;
  });
}

void cmkit_player_free(cmkit_player_t* player) { delete player; }

cmkit_status cmkit_player_set_origin(cmkit_player_t* player, const float origin[3]) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(player);
    CMKIT_REQUIRE(origin);
    cmkit::PlayerState state;
    state.origin = vec(origin);
    state.steps = player->state.steps;
    player->state = state;
    return CMKIT_OK;
  });
}

cmkit_status cmkit_player_step(const cmkit_world_t* world, cmkit_player_t* player, const float wish[3],
                               uint32_t buttons, int32_t steps, cmkit_player_state_t* out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    CMKIT_REQUIRE(player);
    CMKIT_REQUIRE(wish);
    if (steps < 0) return fail(CMKIT_ERROR_INVALID_ARGUMENT, std::string(fn) + ": steps < 0");
    cmkit::PlayerInput input;
    input.wishDir = vec(wish);
    input.jump = (buttons & CMKIT_PLAYER_JUMP) != 0;
    input.crouch = (buttons & CMKIT_PLAYER_CROUCH) != 0;
    input.run = (buttons & CMKIT_PLAYER_RUN) != 0;
    player->state = cmkit::runPlayer(world->world, player->shape, player->state, input, steps,
                                     cmkit::move::kTimeStep, threadWork());
    if (out != nullptr) fillPlayer(player->state, out);
    return CMKIT_OK;
  });
}

cmkit_status cmkit_player_state(const cmkit_player_t* player, cmkit_player_state_t* out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(player);
    CMKIT_REQUIRE(out);
    fillPlayer(player->state, out);
    return CMKIT_OK;
  });
}

}  // extern "C"
