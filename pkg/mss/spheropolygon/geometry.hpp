// Internal to the spheropolygon sources: the distance and crossing tests every image and trial uses.
#pragma once

#include "mss/spheropolygon.hpp"

#include <algorithm>
#include <cmath>

namespace mss::spgeom {

inline double segmentDistance2(const Vec2& p, const Vec2& a, const Vec2& b) {
    const Vec2 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (a + t * ab - p).squaredNorm();
}

/// Whether the horizontal ray from p to +x crosses edge a-b (half-open in y: every crossing counted once).
inline bool crosses(const Vec2& p, const Vec2& a, const Vec2& b) {
    if ((a.y() > p.y()) == (b.y() > p.y())) return false;
    return p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
}

/// Whether p lies within the edge a-b swept by a disc whose radius goes linearly from ra to rb: the convex
/// hull of the discs (a, ra) and (b, rb) (with ra = rb the paper's band of one spheroradius). The distance
/// less the radius, f(t) = |p - (a + t (b - a))| - (ra + t (rb - ra)), is convex in t: its stationary point,
/// clamped to [0, 1], is its minimum.
inline bool nearEdge(const Vec2& p, const Vec2& a, double ra, const Vec2& b, double rb) {
    if (ra == rb) return segmentDistance2(p, a, b) <= ra * ra;
    const Vec2 d = b - a;
    const double len = d.norm(), dr = rb - ra;
    if (len <= std::abs(dr)) // one disc holds the other
        return dr > 0 ? (p - b).squaredNorm() <= rb * rb : (p - a).squaredNorm() <= ra * ra;
    const Vec2 u = d / len, q = p - a;
    const double x = q.dot(u), y = std::abs(u.x() * q.y() - u.y() * q.x()), s = -dr / len;
    const double t = std::clamp((x - s * y / std::sqrt(1 - s * s)) / len, 0.0, 1.0);
    const double r = ra + t * dr, along = x - t * len;
    return along * along + y * y <= r * r;
}

} // namespace mss::spgeom
