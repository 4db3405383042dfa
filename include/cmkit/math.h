// math.h: all of cmkit's math types (Vec3, Mat3, Plane, Bounds, Pluecker,
// Rotation). Scalar type: Real (float). Units: map units; angles in degrees
// unless a parameter says radians.
#pragma once

#include "cmkit/bounds.h"
#include "cmkit/config.h"
#include "cmkit/mat3.h"
#include "cmkit/plane.h"
#include "cmkit/pluecker.h"
#include "cmkit/rotation.h"
#include "cmkit/tolerances.h"
#include "cmkit/vec3.h"
