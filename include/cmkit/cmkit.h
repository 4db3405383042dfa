/* cmkit.h: the C API of cmkit, for every language that can call C (Rust,
 * C#, Go, Zig, Lua, Python's ctypes, engine plugins).
 *
 * Plain C11: opaque handles, status codes, no C++ types, no exceptions
 * across the boundary (every C++ exception, std::bad_alloc included, becomes
 * a status). Link with `pkg-config --libs cmkit` (static library:
 * `pkg-config --static --libs cmkit`, which adds the C++ runtime).
 *
 * CONVENTIONS
 * - Every function that can fail returns a cmkit_status: CMKIT_OK (0) or an
 *   error code; on error cmkit_last_error() holds a message (file:line for
 *   bad input files) for the calling thread until its next failing call.
 *   Outputs are written only on CMKIT_OK, except where a function says so.
 * - Units are map units, angles degrees, +z up. Vectors are float[3] (x, y,
 *   z); orientations are float[9], the three axes as rows (world = origin +
 *   local * axis), NULL meaning the identity.
 * - A world (cmkit_world_t) holds a map's world model and its entities'
 *   models, placed as the engine places them (docs/world.md). Entities are
 *   numbered by cmkit_entity_t ids (0: the world model, "worldspawn");
 *   CMKIT_NO_ENTITY (-1) means none.
 * - A query's trace model (cmkit_trace_model_t) may be NULL: a point.
 *
 * THREAD SAFETY
 * - Queries (cmkit_translate ... cmkit_cast_ray, their batches,
 *   cmkit_player_step) take a const world: any number of threads may query
 *   one world at once. Each calling thread uses scratch memory of its own
 *   (made on its first query, freed when the thread ends).
 * - cmkit_world_set_placement, cmkit_world_set_contents and
 *   cmkit_world_free change the world: call them from one thread, never
 *   while another thread queries that world.
 * - Batches run on `threads` worker threads (0: all processors); answer i is
 *   the single query's answer bit for bit at any thread count.
 */
#ifndef CMKIT_CMKIT_H
#define CMKIT_CMKIT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Status of a call: CMKIT_OK or why it failed (see cmkit_last_error()). */
typedef enum cmkit_status {
  CMKIT_OK = 0,                 /**< done */
  CMKIT_ERROR_INVALID_ARGUMENT, /**< a NULL handle or pointer, a bad count, a bad spec */
  CMKIT_ERROR_FILE,             /**< a file that cannot be read or parsed (message: file:line:column) */
  CMKIT_ERROR_NOT_FOUND,        /**< no entity of that name or id */
  CMKIT_ERROR_REFUSED,          /**< the query refused its input (non-finite, out of range, bad axis) */
  CMKIT_ERROR_OUT_OF_MEMORY,    /**< an allocation failed */
  CMKIT_ERROR_INTERNAL          /**< anything else (a bug: please report it) */
} cmkit_status;

/** The message of the calling thread's last failed call ("" when none).
 *  Valid until that thread's next cmkit call. */
const char* cmkit_last_error(void);
/** The library's version, "MAJOR.MINOR.PATCH". */
const char* cmkit_version(void);

/** @name Content flags (the engine's bits) and masks */
/**@{*/
#define CMKIT_CONTENTS_SOLID 0x1u                 /**< blocks movement */
#define CMKIT_CONTENTS_OPAQUE 0x2u                /**< blocks sight */
#define CMKIT_CONTENTS_WATER 0x4u                 /**< water */
#define CMKIT_CONTENTS_PLAYERCLIP 0x8u            /**< blocks players */
#define CMKIT_CONTENTS_MONSTERCLIP 0x10u          /**< blocks monsters */
#define CMKIT_CONTENTS_MOVEABLECLIP 0x20u         /**< blocks moveables */
#define CMKIT_CONTENTS_IKCLIP 0x40u               /**< inverse-kinematics clip */
#define CMKIT_CONTENTS_BLOOD 0x80u                /**< hit by blood decals */
#define CMKIT_CONTENTS_BODY 0x100u                /**< an actor's body */
#define CMKIT_CONTENTS_PROJECTILE 0x200u          /**< a projectile */
#define CMKIT_CONTENTS_CORPSE 0x400u              /**< a corpse */
#define CMKIT_CONTENTS_RENDERMODEL 0x800u         /**< a render model */
#define CMKIT_CONTENTS_TRIGGER 0x1000u            /**< a trigger volume */
#define CMKIT_CONTENTS_AAS_SOLID 0x2000u          /**< solid for AI navigation */
#define CMKIT_CONTENTS_AAS_OBSTACLE 0x4000u       /**< an obstacle for AI navigation */
#define CMKIT_CONTENTS_FLASHLIGHT_TRIGGER 0x8000u /**< triggered by a flashlight */
#define CMKIT_MASK_ALL 0xFFFFFFFFu                /**< every flag */
#define CMKIT_MASK_SOLID CMKIT_CONTENTS_SOLID     /**< what blocks ordinary traces */
/** What blocks a player. */
#define CMKIT_MASK_PLAYER_SOLID (CMKIT_CONTENTS_SOLID | CMKIT_CONTENTS_PLAYERCLIP | CMKIT_CONTENTS_BODY)
/** What blocks a monster. */
#define CMKIT_MASK_MONSTER_SOLID (CMKIT_CONTENTS_SOLID | CMKIT_CONTENTS_MONSTERCLIP | CMKIT_CONTENTS_BODY)
#define CMKIT_MASK_OPAQUE CMKIT_CONTENTS_OPAQUE /**< what blocks sight */
#define CMKIT_MASK_WATER CMKIT_CONTENTS_WATER   /**< water */
/**@}*/

/** An entity's id in a world; CMKIT_NO_ENTITY: none. */
typedef int32_t cmkit_entity_t;
/** No entity (a miss). */
#define CMKIT_NO_ENTITY (-1)

/** A world: a map's models placed (opaque). */
typedef struct cmkit_world cmkit_world_t;
/** A trace model: the convex shape a query moves (opaque). */
typedef struct cmkit_trace_model cmkit_trace_model_t;

/** Which features touched (cmkit_trace_t::contact_type). */
typedef enum cmkit_contact_type {
  CMKIT_CONTACT_NONE = 0,         /**< no contact */
  CMKIT_CONTACT_EDGE = 1,         /**< a trace-model edge met a model edge */
  CMKIT_CONTACT_MODEL_VERTEX = 2, /**< a model vertex met a trace-model polygon */
  CMKIT_CONTACT_TRM_VERTEX = 3    /**< a trace-model vertex met a model polygon */
} cmkit_contact_type;

/** The answer of a translation or rotation. */
typedef struct cmkit_trace {
  float fraction;        /**< how far the move got, 0..1 (1: nothing hit) */
  float end[3];          /**< the trace model's position at the end */
  float end_axis[9];     /**< its orientation at the end (rows) */
  float point[3];        /**< the contact point (zero on a miss) */
  float normal[3];       /**< the contact plane's normal, facing the trace model */
  float dist;            /**< normal . p = dist on the contact plane */
  uint32_t contents;     /**< contents of the surface hit */
  int32_t material;      /**< material index in the hit entity's model, -1: none */
  cmkit_entity_t entity; /**< the entity hit; CMKIT_NO_ENTITY on a miss */
  int32_t contact_type;  /**< a cmkit_contact_type */
  int32_t start_solid;   /**< 1: the start overlaps something matching the mask */
} cmkit_trace_t;

/** One contact of cmkit_contacts. */
typedef struct cmkit_contact {
  float point[3];        /**< where */
  float normal[3];       /**< the contact plane's normal, facing the trace model */
  float dist;            /**< normal . p = dist */
  uint32_t contents;     /**< contents of the surface */
  int32_t material;      /**< material index, -1: none */
  cmkit_entity_t entity; /**< whose model */
  int32_t contact_type;  /**< a cmkit_contact_type */
} cmkit_contact_t;

/** The answer of a ray cast. */
typedef struct cmkit_ray_hit {
  float fraction;        /**< where the segment crosses the first front face, 1: none */
  float point[3];        /**< the crossing */
  float normal[3];       /**< the face's normal */
  uint32_t contents;     /**< its contents */
  int32_t material;      /**< material index, -1: none */
  cmkit_entity_t entity; /**< whose model; CMKIT_NO_ENTITY on a miss */
} cmkit_ray_hit_t;

/* ---- worlds ---- */

/** Loads a map's world: a .map (NAME.cm beside it is used when its CRC
 *  matches, NAME.proc prunes the world model) or a .cm file (its models;
 *  entities placed from NAME.map beside it when that exists, else every
 *  model at the origin). Default materials (docs/materials.md). */
cmkit_status cmkit_load_map(const char* path, cmkit_world_t** out);
/** Frees a world (NULL: nothing). */
void cmkit_world_free(cmkit_world_t* world);
/** One past the largest entity id (ids 0 .. count-1 may be asked about). */
int32_t cmkit_world_entity_limit(const cmkit_world_t* world);
/** The entity named `name` (the lowest id of that name). */
cmkit_status cmkit_world_find_entity(const cmkit_world_t* world, const char* name, cmkit_entity_t* out);
/** An entity's name, or NULL for an id with no entity. Valid while the world lives. */
const char* cmkit_world_entity_name(const cmkit_world_t* world, cmkit_entity_t entity);
/** An entity's placement: origin and (when axis is not NULL) orientation. */
cmkit_status cmkit_world_get_placement(const cmkit_world_t* world, cmkit_entity_t entity, float origin[3],
                                       float axis[9]);
/** Moves an entity (a door opening, a lift): origin, orientation (NULL:
 *  identity). Not while another thread queries the world. */
cmkit_status cmkit_world_set_placement(cmkit_world_t* world, cmkit_entity_t entity, const float origin[3],
                                       const float axis[9]);
/** Sets what an entity collides as (0: nothing). Not while another thread
 *  queries the world. */
cmkit_status cmkit_world_set_contents(cmkit_world_t* world, cmkit_entity_t entity, uint32_t contents);

/* ---- trace models ---- */

/** An axis-aligned box from (x0, y0, z0) to (x1, y1, z1) around its origin. */
cmkit_status cmkit_trace_model_box(float x0, float y0, float z0, float x1, float y1, float z1,
                                   cmkit_trace_model_t** out);
/** A cylinder of `sides` sides (3..10) filling the box's bounds, axis +z. */
cmkit_status cmkit_trace_model_cylinder(float x0, float y0, float z0, float x1, float y1, float z1, int sides,
                                        cmkit_trace_model_t** out);
/** A cone of `sides` sides (3..10) filling the box's bounds, tip up. */
cmkit_status cmkit_trace_model_cone(float x0, float y0, float z0, float x1, float y1, float z1, int sides,
                                    cmkit_trace_model_t** out);
/** Any trace model of the query format's specs ("box:-16,-16,0,16,16,72",
 *  "cylinder:8:...", "octahedron:...", "dodecahedron:...", "bone:...",
 *  "point"; docs/query-format.md). */
cmkit_status cmkit_trace_model_from_spec(const char* spec, cmkit_trace_model_t** out);
/** Frees a trace model (NULL: nothing). */
void cmkit_trace_model_free(cmkit_trace_model_t* trm);

/* ---- queries ---- */

/** Moves `trm` (NULL: a point), oriented by `trm_axis` (NULL: identity),
 *  from `start` to `end` through the world; stops 0.25 units in front of
 *  the first surface whose contents meet `mask`. CMKIT_ERROR_REFUSED when
 *  the input is refused (out is then written with fraction 0). */
cmkit_status cmkit_translate(const cmkit_world_t* world, const cmkit_trace_model_t* trm,
                             const float trm_axis[9], const float start[3], const float end[3], uint32_t mask,
                             cmkit_trace_t* out);
/** Turns `trm` at `start` by `angle` degrees about the line through
 *  `rot_origin` along the unit vector `rot_axis`. */
cmkit_status cmkit_rotate(const cmkit_world_t* world, const cmkit_trace_model_t* trm, const float trm_axis[9],
                          const float start[3], const float rot_origin[3], const float rot_axis[3],
                          float angle, uint32_t mask, cmkit_trace_t* out);
/** What a placed trace model overlaps: the OR of the contents met
 *  (`contents`, 0: free) and the lowest entity overlapped (`entity`, may be
 *  NULL). */
cmkit_status cmkit_contents(const cmkit_world_t* world, const cmkit_trace_model_t* trm,
                            const float trm_axis[9], const float position[3], uint32_t mask,
                            uint32_t* contents, cmkit_entity_t* entity);
/** The contents of the brushes containing a point (the OR over the world);
 *  `entity` (may be NULL): the lowest entity with contents there. */
cmkit_status cmkit_point_contents(const cmkit_world_t* world, const float point[3], uint32_t* contents,
                                  cmkit_entity_t* entity);
/** Every contact of `trm` moved from `start` by `dir` * `depth`: at most
 *  `capacity` written to `out`, their number to `count`. */
cmkit_status cmkit_contacts(const cmkit_world_t* world, const cmkit_trace_model_t* trm,
                            const float trm_axis[9], const float start[3], const float dir[3], float depth,
                            uint32_t mask, cmkit_contact_t* out, int32_t capacity, int32_t* count);
/** The first front face the segment start -> end crosses. */
cmkit_status cmkit_cast_ray(const cmkit_world_t* world, const float start[3], const float end[3],
                            uint32_t mask, cmkit_ray_hit_t* out);

/* ---- batches: arrays of n queries, `threads` workers (0: all processors) ---- */

/** out[i] = cmkit_translate(starts + 3i -> ends + 3i). A refused query is
 *  not an error of the batch: its out[i].fraction is 0 and its
 *  contact_type CMKIT_CONTACT_NONE. */
cmkit_status cmkit_translate_batch(const cmkit_world_t* world, const cmkit_trace_model_t* trm,
                                   const float trm_axis[9], const float* starts, const float* ends, size_t n,
                                   uint32_t mask, int threads, cmkit_trace_t* out);
/** contents[i] (and entities[i] when not NULL) = cmkit_point_contents(points + 3i). */
cmkit_status cmkit_point_contents_batch(const cmkit_world_t* world, const float* points, size_t n,
                                        int threads, uint32_t* contents, cmkit_entity_t* entities);
/** out[i] = cmkit_cast_ray(starts + 3i -> ends + 3i). */
cmkit_status cmkit_cast_ray_batch(const cmkit_world_t* world, const float* starts, const float* ends,
                                  size_t n, uint32_t mask, int threads, cmkit_ray_hit_t* out);

/* ---- the player move (docs/movement.md) ---- */

/** A player walking through a world: its shape and its state between steps
 *  (opaque; cmkit_player_state reads the state). */
typedef struct cmkit_player cmkit_player_t;

/** What the player wants (cmkit_player_step's `buttons`, or-ed). */
typedef enum cmkit_player_button {
  CMKIT_PLAYER_JUMP = 1,   /**< jump (a new press on the ground jumps) */
  CMKIT_PLAYER_CROUCH = 2, /**< crouch */
  CMKIT_PLAYER_RUN = 4     /**< run instead of walk */
} cmkit_player_button;

/** A player's state after its last step. */
typedef struct cmkit_player_state {
  float origin[3];              /**< the feet: bottom centre of the shape */
  float velocity[3];            /**< units per second */
  float ground_normal[3];       /**< the ground's normal (on_ground), else zero */
  cmkit_entity_t ground_entity; /**< the entity stood on, CMKIT_NO_ENTITY in the air */
  int32_t on_ground;            /**< 1: on walkable ground */
  int32_t crouched;             /**< 1: the crouched shape is in use */
  int32_t stuck;                /**< 1: the step started in solid and could not get free */
  int64_t steps;                /**< steps taken */
} cmkit_player_state_t;

/** A player standing at `origin` (its feet): the engine's box (32 x 32 x 74,
 *  38 crouched) when `shape` is NULL, else that trace model (origin at its
 *  feet; crouching keeps it). Doom 3's parameters: gravity 1066, steps up
 *  to 16 units, jumps 48 high, walks 140 units/s. */
cmkit_status cmkit_player_create(const cmkit_trace_model_t* shape, const float origin[3],
                                 cmkit_player_t** out);
/** Frees a player (NULL: nothing). */
void cmkit_player_free(cmkit_player_t* player);
/** Moves the player to `origin`, at rest (a respawn, a teleport). */
cmkit_status cmkit_player_set_origin(cmkit_player_t* player, const float origin[3]);
/** Runs `steps` steps of 1/60 s through the world, wishing to walk along
 *  `wish` (world space, z ignored, its length the fraction of full speed,
 *  at most 1) with `buttons` (cmkit_player_button bits) held; the state
 *  after the last step goes to `out` (may be NULL). Deterministic: the
 *  same calls give the same bits. A player stands on moving entities:
 *  move them with cmkit_world_set_placement between calls and the next
 *  step carries it along. Several threads may step different players
 *  through one world at once. */
cmkit_status cmkit_player_step(const cmkit_world_t* world, cmkit_player_t* player, const float wish[3],
                               uint32_t buttons, int32_t steps, cmkit_player_state_t* out);
/** The player's state after its last step. */
cmkit_status cmkit_player_state(const cmkit_player_t* player, cmkit_player_state_t* out);

#ifdef __cplusplus
}
#endif

#endif /* CMKIT_CMKIT_H */
