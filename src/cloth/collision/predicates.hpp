#pragma once
/// Exact orientation predicates (Shewchuk 1997): a floating-point filter, then exact expansion
/// arithmetic when the filter cannot decide. Signs are exact for any finite double inputs
/// (barring overflow/underflow).
#include "core/types.hpp"

namespace dexcloth::collision {

/// Sign (−1, 0, +1) of det[b − a, c − a, d − a]: +1 when d lies on the side of plane (a, b, c)
/// that its normal (b − a) × (c − a) points to.
int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Sign (−1, 0, +1) of det[b − a, c − a] for 2-D points: +1 when (a, b, c) turns counter-clockwise.
int orient2d(const Vec2& a, const Vec2& b, const Vec2& c);

}  // namespace dexcloth::collision
