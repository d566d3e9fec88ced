/* Making the bodies of a test world: the body definition most tests fill, with the
 * creation checked. Shared by the cast and character tests. */
#ifndef NTILE_TESTS_BODIES_H
#define NTILE_TESTS_BODIES_H

#include "ntile/ntile.h"

/* A body of the given type and shape at (x, y) (world units), every other field the
 * default; the test fails when nt_body_create refuses it. */
nt_body_id test_body(nt_world *w, nt_body_type type, nt_shape s, double x, double y);

#endif
