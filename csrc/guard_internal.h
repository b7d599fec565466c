/* SPDX-License-Identifier: MIT */
/*
 * Internal helpers of the collision guard (geometry.c, guard.c): 3-D vector algebra and the exact
 * distance routines. Not part of the public API.
 */
#ifndef CRANE_GUARD_INTERNAL_H
#define CRANE_GUARD_INTERNAL_H

#include "crane_internal.h"

/* Keeps a helper out of line so that its locals are not stacked on its caller's frame along every
 * path (the stack budget of docs/embedding.md is per entry point's deepest path). */
#if defined(__GNUC__)
#define CRANE__NOINLINE __attribute__((noinline))
#else
#define CRANE__NOINLINE
#endif

typedef struct {
    crane_real x, y, z;
} crane__v3;

static inline crane__v3 crane__v3_make(crane_real x, crane_real y, crane_real z)
{
    crane__v3 v;
    v.x = x;
    v.y = y;
    v.z = z;
    return v;
}

static inline crane__v3 crane__v3_load(const crane_real a[3]) { return crane__v3_make(a[0], a[1], a[2]); }
static inline void crane__v3_store(crane_real a[3], crane__v3 v) { a[0] = v.x; a[1] = v.y; a[2] = v.z; }
static inline crane__v3 crane__v3_add(crane__v3 a, crane__v3 b) { return crane__v3_make(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline crane__v3 crane__v3_sub(crane__v3 a, crane__v3 b) { return crane__v3_make(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline crane__v3 crane__v3_scale(crane_real s, crane__v3 a) { return crane__v3_make(s * a.x, s * a.y, s * a.z); }
static inline crane_real crane__v3_dot(crane__v3 a, crane__v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline crane_real crane__v3_norm(crane__v3 a) { return crane__sqrt(crane__v3_dot(a, a)); }

/* A coordinate or size the guard accepts: finite and within CRANE_GUARD_LENGTH_MAX. */
static inline int crane__length_ok(crane_real x)
{
    return crane__finite(x) && crane__fabs(x) <= (crane_real)CRANE_GUARD_LENGTH_MAX;
}

/* Closest points of two solids (crane_solid_distance without the argument checks): the distance
 * between their surfaces, 0 if they touch or overlap; *pa on a, *pb on b. Returns 0 for a pair of
 * kinds it does not handle (two planes). */
int crane__solid_distance(const crane_solid *a, const crane_solid *b, crane_real *distance,
                          crane__v3 *pa, crane__v3 *pb);

/* The checks of one solid: 0 if valid, else the CRANE_GUARD_FIELD_* of the first bad field. */
int crane__solid_field(const crane_solid *s);

/* The messages of the guard's status codes (crane_status_message's fallback). */
const char *crane__guard_status_message(crane_status status);

#endif /* CRANE_GUARD_INTERNAL_H */
