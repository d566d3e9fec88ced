/* bench-peers — a C interface to the few Box2D 2.4 calls the benchmark needs
 * (Box2D 2.4 is C++; box2d_shim.cpp is the only C++ file of the project and is
 * compiled only by `make bench-peers`). Units are Box2D's (metres, seconds). */
#ifndef NTILE_BOX2D_SHIM_H
#define NTILE_BOX2D_SHIM_H

#ifdef __cplusplus
extern "C" {
#endif

typedef struct b2s_world b2s_world;

/* A world with this gravity; sleeping allowed or not; continuous collision (against
 * static shapes, Box2D's default) on or off. NULL when out of memory. */
b2s_world *b2s_create(double gx, double gy, int allow_sleep, int continuous, int body_capacity);
void b2s_destroy(b2s_world *w);
/* A static closed chain (one-sided: collides on the right of each edge a->b, in a
 * y-up frame). */
void b2s_add_loop(b2s_world *w, const double *xy, int count, double friction, double restitution,
                  double restitution_threshold, unsigned category);
/* A dynamic body with fixed rotation, box (half-sizes hx, hy) or circle (radius hx),
 * of the given mass; collides with fixtures whose category meets mask. Returns its index. */
int b2s_add_body(b2s_world *w, int circle, double hx, double hy, double x, double y, double vx, double vy,
                 double mass, double friction, double restitution, double restitution_threshold, unsigned category,
                 unsigned mask, int allow_sleep);
void b2s_step(b2s_world *w, double dt, int velocity_iterations, int position_iterations);
/* x, y, vx, vy of every body, in creation order. */
void b2s_read(const b2s_world *w, double *out);
int b2s_awake(const b2s_world *w);

#ifdef __cplusplus
}
#endif

#endif
