/* See bodies.h. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "bodies.h"

nt_body_id test_body(nt_world *w, nt_body_type type, nt_shape s, double x, double y)
{
    nt_body_def d = nt_default_body_def();
    d.type = type;
    d.shape = s;
    d.position = nt_v2((nt_real)x, (nt_real)y);
    nt_body_id id;
    assert_int_equal(nt_body_create(w, &d, &id), NT_OK);
    return id;
}
