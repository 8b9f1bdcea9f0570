// The layer analysis of Tools/Polar/Layers.h (friction mobilisation and stress by distance from the
// faces of the box) on hand-made contact sets whose answers are worked out in the comments.
#include "Core/Error.h"
#include "Layers.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

using namespace pdpm;
using namespace pdpm::tools;

namespace {

ContactRecord contactAt(double z, Vec3 normal, double fn, Vec3 ft, Vec3 branch, bool sliding = false, int j = 1) {
    ContactRecord c;
    c.i = 0;
    c.j = j;
    c.contactPoint = {0.5, 0.5, z};
    c.normal = normal;
    c.fn = fn;
    c.ft = ft;
    c.branch = branch;
    c.sliding = sliding;
    return c;
}

/// Unit box, two layers along z: d/L in [0, 0.25) (next to the faces) and [0.25, 0.5] (the middle).
ContactSnapshot handMade() {
    ContactSnapshot s;
    s.boxLo = {0, 0, 0};
    s.boxHi = {1, 1, 1};
    const double mu = 0.5;
    // next to the faces: z = 0.05, z = 0.98 (d = 0.02) and z = 1.1 (an image contact point outside
    // the box: wraps to 0.1), all at the Coulomb limit |f_t| = mu f_n
    s.contacts.push_back(contactAt(0.05, {0, 0, 1}, 2, {mu * 2, 0, 0}, {0, 0, 0.1}, true));
    s.contacts.push_back(contactAt(0.98, {0, 0, 1}, 2, {0, mu * 2, 0}, {0, 0, 0.1}, true));
    s.contacts.push_back(contactAt(1.1, {0, 0, 1}, 4, {0, 0.6 * mu * 4, 0}, {0, 0, 0.1}, false));
    // the middle: z = 0.3 and z = -0.4 (wraps to 0.6, d = 0.4), no tangential force
    s.contacts.push_back(contactAt(0.3, {0, 0, 1}, 2, {0, 0, 0}, {0, 0, 0.1}));
    s.contacts.push_back(contactAt(-0.4, {1, 0, 0}, 1, {0, 0, 0}, {0.1, 0, 0}));
    // a wall contact in the middle (ignored unless walls are included) and a contact without force
    // (in the stress and the count, not among the loaded contacts)
    s.contacts.push_back(contactAt(0.5, {0, 0, 1}, 10, {0, 0, 0}, {0, 0, 0.1}, false, -1));
    s.contacts.push_back(contactAt(0.5, {0, 0, 1}, 0, {0, 0, 0}, {0, 0, 0.1}));
    return s;
}

} // namespace

TEST(Layers, MobilisationAndStressOfHandMadeContacts) {
    const auto layers = analyseLayers(handMade(), 2, 2, 0.5, false);
    ASSERT_EQ(layers.size(), 2u);
    EXPECT_DOUBLE_EQ(layers[0].lo, 0.0);
    EXPECT_DOUBLE_EQ(layers[0].hi, 0.25);
    EXPECT_DOUBLE_EQ(layers[1].hi, 0.5);
    // faces: psi = (1 + 1 + 0.6)/3, two of three sliding
    EXPECT_EQ(layers[0].contacts, 3);
    EXPECT_NEAR(layers[0].psi, 2.6 / 3, 1e-15);
    EXPECT_NEAR(layers[0].sliding, 2.0 / 3, 1e-15);
    // middle: psi 0; sigma = (1/V_layer) sum f (x) b with V_layer = 1/2:
    // zz = 2 * 0.1 / 0.5 = 0.4, xx = 1 * 0.1 / 0.5 = 0.2, yy = 0; p = 0.2;
    // deviator diag(0, -0.2, 0.2): sqrt(3 J2) = sqrt(3 * 0.04) -> s_dev = sqrt(0.12)/0.2;
    // axial over lateral = 0.4 / ((0.2 + 0)/2) = 4
    EXPECT_EQ(layers[1].contacts, 3);
    EXPECT_EQ(layers[1].loaded, 2);
    EXPECT_DOUBLE_EQ(layers[1].psi, 0.0);
    EXPECT_DOUBLE_EQ(layers[1].sliding, 0.0);
    EXPECT_NEAR(layers[1].sigma[2][2], 0.4, 1e-15);
    EXPECT_NEAR(layers[1].sigma[0][0], 0.2, 1e-15);
    EXPECT_NEAR(layers[1].p, 0.2, 1e-15);
    EXPECT_NEAR(layers[1].sDev, std::sqrt(0.12) / 0.2, 1e-12);
    EXPECT_NEAR(layers[1].axialOverLateral, 4.0, 1e-12);
    // fabric of the middle: three contacts, two along z and one along x (the unloaded one counts):
    // F_zz = 2/3, F_xx = 1/3 -> F_zz - (F_xx + F_yy)/2 = 2/3 - 1/6 = 1/2
    EXPECT_NEAR(layers[1].fabric[2][2], 2.0 / 3, 1e-15);
    EXPECT_NEAR(layers[1].fabricAxialStar, 0.5, 1e-15);
    // the faces: all three along z -> 1
    EXPECT_NEAR(layers[0].fabricAxialStar, 1.0, 1e-15);
    // faces: the tangential forces make f (x) b asymmetric; the stress is its symmetric part:
    // xz = (1/2)(1 * 0.1)/0.5 = 0.1 from the first contact, yz = (1/2)(1 * 0.1 + 1.2 * 0.1)/0.5 = 0.22
    EXPECT_NEAR(layers[0].sigma[0][2], 0.1, 1e-15);
    EXPECT_NEAR(layers[0].sigma[2][0], 0.1, 1e-15);
    EXPECT_NEAR(layers[0].sigma[1][2], 0.22, 1e-15);
    EXPECT_NEAR(layers[0].sigma[2][2], (2 + 2 + 4) * 0.1 / 0.5, 1e-15);
}

TEST(Layers, WallContactsOnlyWhenAsked) {
    const auto with = analyseLayers(handMade(), 2, 2, 0.5, true);
    EXPECT_EQ(with[1].contacts, 4);
    EXPECT_EQ(with[1].loaded, 3);
    EXPECT_NEAR(with[1].sigma[2][2], (2 + 10) * 0.1 / 0.5, 1e-15);
}

TEST(Layers, ShiftingEveryContactByABoxLengthChangesNothing) {
    for (double shift : {3.0, -3.0}) {
        ContactSnapshot a = handMade(), b = handMade();
        for (auto& c : b.contacts) c.contactPoint.z += shift;
        // three layers: edges at d/L = 1/6 and 1/3, away from every contact point (an edge is where
        // round-off may decide)
        const auto la = analyseLayers(a, 2, 3, 0.5, false), lb = analyseLayers(b, 2, 3, 0.5, false);
        for (std::size_t k = 0; k < la.size(); ++k) {
            EXPECT_EQ(la[k].contacts, lb[k].contacts) << shift << " " << k;
            EXPECT_NEAR(la[k].psi, lb[k].psi, 1e-12) << shift << " " << k;
            EXPECT_NEAR(la[k].sigma[2][2], lb[k].sigma[2][2], 1e-12) << shift << " " << k;
        }
    }
}

TEST(Layers, OffsetBoxAlongXAndTheMeanOfTheLayersIsTheWholeSample) {
    // box [-1, 1] x [2, 5] x [0.5, 4.5] (L = 2, 3, 4, V = 24), layers along x
    ContactSnapshot s;
    s.boxLo = {-1, 2, 0.5};
    s.boxHi = {1, 5, 4.5};
    // one contact at x = -0.9 (d = 0.1 of 2: d/L = 0.05), one at x = 0.1 (d/L = 0.45), along x and y
    ContactRecord a = contactAt(0, {1, 0, 0}, 3, {0, 0.5, 0}, {0.2, 0, 0});
    a.contactPoint = {-0.9, 3, 1};
    ContactRecord b = contactAt(0, {0, 1, 0}, 2, {0, 0, 0}, {0, 0.2, 0});
    b.contactPoint = {0.1, 4, 4};
    // a tensile contact (f_n < 0: adhesion, or an unclipped dashpot) in the second layer
    ContactRecord c = contactAt(0, {1, 0, 0}, -1, {0, 0, 0}, {0.2, 0, 0});
    c.contactPoint = {-0.2, 2.5, 3};  // d = 0.8 of 2: d/L = 0.4
    s.contacts = {a, b, c};
    const auto two = analyseLayers(s, 0, 2, 0.5, false);
    // V_layer = 12: layer 0 (d/L < 0.25) holds a: xx = 3 * 0.2 / 12 = 0.05, yx sym = 0.5 * 0.5 * 0.2 / 12
    EXPECT_EQ(two[0].contacts, 1);
    EXPECT_NEAR(two[0].sigma[0][0], 0.05, 1e-15);
    EXPECT_NEAR(two[0].sigma[0][1], 0.05 / 12, 1e-15);
    EXPECT_NEAR(two[0].psi, 0.5 / (0.5 * 3), 1e-15);
    // layer 1 holds b and c: yy = 2 * 0.2 / 12, xx = -1 * 0.2 / 12; psi over b alone (c is not loaded)
    EXPECT_EQ(two[1].contacts, 2);
    EXPECT_EQ(two[1].loaded, 1);
    EXPECT_NEAR(two[1].sigma[1][1], 0.4 / 12, 1e-15);
    EXPECT_NEAR(two[1].sigma[0][0], -0.2 / 12, 1e-15);
    EXPECT_DOUBLE_EQ(two[1].psi, 0.0);
    // axial (x) over lateral: layer 0 has no lateral stress -> not a number; layer 1: (-0.2/12) / (0.2/12)
    EXPECT_TRUE(std::isnan(two[0].axialOverLateral));
    EXPECT_NEAR(two[1].axialOverLateral, -1.0, 1e-12);
    // fabric along x: layer 0 one contact along x -> 1; layer 1 one along y, one along x -> 1/2 - 1/4
    EXPECT_NEAR(two[0].fabricAxialStar, 1.0, 1e-15);
    EXPECT_NEAR(two[1].fabricAxialStar, 0.25, 1e-15);
    // the mean of the layers' stress is (1/V) sum f (x) b over all contacts, for any number of layers
    for (int n : {1, 3, 7}) {
        const auto layers = analyseLayers(s, 0, n, 0.5, false);
        std::array<std::array<double, 3>, 3> mean{};
        for (const auto& l : layers)
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) mean[i][j] += l.sigma[i][j] / n;
        EXPECT_NEAR(mean[0][0], (3 * 0.2 - 1 * 0.2) / 24, 1e-15) << n;
        EXPECT_NEAR(mean[1][1], 2 * 0.2 / 24, 1e-15) << n;
        EXPECT_NEAR(mean[0][1], 0.5 * 0.5 * 0.2 / 24, 1e-15) << n;
        EXPECT_NEAR(mean[2][2], 0.0, 1e-15) << n;
    }
}

TEST(Layers, EmptyLayersAreNotNumbers) {
    const auto layers = analyseLayers(handMade(), 2, 50, 0.5, false);
    int empty = 0;
    for (const auto& l : layers)
        if (l.contacts == 0) {
            ++empty;
            EXPECT_TRUE(std::isnan(l.psi) && std::isnan(l.sliding) && std::isnan(l.sDev) && std::isnan(l.axialOverLateral) &&
                        std::isnan(l.fabricAxialStar));
        }
    EXPECT_GT(empty, 40);
}

TEST(Layers, BadArgumentsAreRefused) {
    const ContactSnapshot s = handMade();
    EXPECT_THROW(analyseLayers(s, 3, 2, 0.5, false), InputError);
    EXPECT_THROW(analyseLayers(s, 2, 0, 0.5, false), InputError);
    EXPECT_THROW(analyseLayers(s, 2, 2, 0.0, false), InputError);
    ContactSnapshot flat = s;
    flat.boxHi.z = 0;
    EXPECT_THROW(analyseLayers(flat, 2, 2, 0.5, false), InputError);
    ContactSnapshot inverted = s;  // two negative extents: a positive product, still no box
    inverted.boxHi.x = inverted.boxHi.y = -1;
    EXPECT_THROW(analyseLayers(inverted, 2, 2, 0.5, false), InputError);
}
