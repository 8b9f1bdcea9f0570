#include "InSitu.h"

namespace pdpm::tools {

namespace {
template <class S>
void copyDomain(const DPMBase& d, S& s) {
    s.time = d.time();
    s.step = d.step();
    s.boxLo = d.box().lo();
    s.boxHi = d.box().hi();
    for (int a = 0; a < 3; ++a) s.periodic[a] = d.box().periodic(a);
}
} // namespace

ParticleSnapshot particleSnapshot(const DPMBase& d) {
    ParticleSnapshot s;
    copyDomain(d, s);
    const ParticleData& P = d.particles();
    s.x = P.x;
    s.v = P.v;
    // wrapped as the next neighbour-list build would: across a wall-driven boundary the velocity too
    for (std::size_t i = 0; i < s.x.size(); ++i) s.v[i] += d.box().wrapWithVelocityShift(s.x[i]);
    s.r = P.r;
    s.m = P.m;
    s.omega = P.w;
    s.species.assign(P.species.begin(), P.species.end());
    s.fixed.assign(P.fixed.begin(), P.fixed.end());
    if (d.contactsAreCurrent()) {
        s.coordination.assign(P.size(), 0);
        s.force.assign(P.size(), Vec3{});
        for (const auto& c : d.contacts()) {
            const Vec3 f = c.fn * c.n + c.ft;
            ++s.coordination[c.i];
            s.force[c.i] += f;
            if (c.j >= 0) {
                ++s.coordination[c.j];
                s.force[c.j] -= f;
            }
        }
    }
    return s;
}

ContactSnapshot contactSnapshot(const DPMBase& d) {
    ContactSnapshot s;
    copyDomain(d, s);
    s.contacts.reserve(d.contacts().size());
    for (const auto& c : d.contacts()) {
        ContactRecord r;
        r.i = c.i;
        r.j = c.j;
        r.contactPoint = c.point;
        r.normal = c.n;
        r.ft = c.ft;
        r.branch = c.branch;
        r.overlap = c.overlap;
        r.fn = c.fn;
        r.sliding = c.sliding;
        s.contacts.push_back(r);
    }
    return s;
}

} // namespace pdpm::tools
