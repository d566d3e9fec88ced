// bench-peers — the C interface to Box2D 2.4 (see box2d_shim.h). The smallest C++
// the benchmark needs; everything else about the scenes is in box2d.c.
#include <box2d/box2d.h>
#include <new>
#include <vector>
#include "box2d_shim.h"

struct b2s_world {
    b2World world;
    std::vector<b2Body *> bodies;
    explicit b2s_world(const b2Vec2 &g) : world(g) {}
};

extern "C" b2s_world *b2s_create(double gx, double gy, int allow_sleep, int continuous, int body_capacity)
{
    b2s_world *w = new (std::nothrow) b2s_world(b2Vec2((float)gx, (float)gy));
    if (!w) return nullptr;
    w->world.SetAllowSleeping(allow_sleep != 0);
    w->world.SetContinuousPhysics(continuous != 0);
    w->bodies.reserve((size_t)(body_capacity > 0 ? body_capacity : 1));
    return w;
}

extern "C" void b2s_destroy(b2s_world *w) { delete w; }

extern "C" void b2s_add_loop(b2s_world *w, const double *xy, int count, double friction, double restitution,
                             double restitution_threshold, unsigned category)
{
    std::vector<b2Vec2> v((size_t)count);
    for (int i = 0; i < count; i++) v[(size_t)i].Set((float)xy[2 * i], (float)xy[2 * i + 1]);
    b2BodyDef bd;
    b2Body *ground = w->world.CreateBody(&bd);
    b2ChainShape chain;
    chain.CreateLoop(v.data(), count);
    b2FixtureDef fd;
    fd.shape = &chain;
    fd.friction = (float)friction;
    fd.restitution = (float)restitution;
    fd.restitutionThreshold = (float)restitution_threshold;
    fd.filter.categoryBits = (uint16)category;
    fd.filter.maskBits = 0xFFFF;
    ground->CreateFixture(&fd);
}

extern "C" int b2s_add_body(b2s_world *w, int circle, double hx, double hy, double x, double y, double vx, double vy,
                            double mass, double friction, double restitution, double restitution_threshold,
                            unsigned category, unsigned mask, int allow_sleep)
{
    b2BodyDef bd;
    bd.type = b2_dynamicBody;
    bd.position.Set((float)x, (float)y);
    bd.linearVelocity.Set((float)vx, (float)vy);
    bd.fixedRotation = true;
    bd.allowSleep = allow_sleep != 0;
    b2Body *body = w->world.CreateBody(&bd);
    b2PolygonShape box;
    b2CircleShape disc;
    double area;
    b2FixtureDef fd;
    if (circle) {
        disc.m_radius = (float)hx;
        fd.shape = &disc;
        area = b2_pi * hx * hx;
    } else {
        box.SetAsBox((float)hx, (float)hy);
        fd.shape = &box;
        area = 4 * hx * hy;
    }
    fd.density = (float)(mass / area);
    fd.friction = (float)friction;
    fd.restitution = (float)restitution;
    fd.restitutionThreshold = (float)restitution_threshold;
    fd.filter.categoryBits = (uint16)category;
    fd.filter.maskBits = (uint16)mask;
    body->CreateFixture(&fd);
    w->bodies.push_back(body);
    return (int)w->bodies.size() - 1;
}

extern "C" void b2s_step(b2s_world *w, double dt, int velocity_iterations, int position_iterations)
{
    w->world.Step((float)dt, velocity_iterations, position_iterations);
}

extern "C" void b2s_read(const b2s_world *w, double *out)
{
    for (size_t i = 0; i < w->bodies.size(); i++) {
        const b2Vec2 &p = w->bodies[i]->GetPosition(), &v = w->bodies[i]->GetLinearVelocity();
        out[4 * i] = p.x, out[4 * i + 1] = p.y, out[4 * i + 2] = v.x, out[4 * i + 3] = v.y;
    }
}

extern "C" int b2s_awake(const b2s_world *w)
{
    int n = 0;
    for (b2Body *b : w->bodies) n += b->IsAwake();
    return n;
}
