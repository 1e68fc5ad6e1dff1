// A symmetric 3x3 tensor field (B or Gs) stored as its independent components only.
//
// 3D: xx, yy, zz, xy, xz, yz. 2D (z-invariant, no z motion): xx, yy, xy; the zz
// component obeys D Tzz/Dt = 2 L_zz Tzz = 0 and xz, yz stay 0, so they are not stored:
// `value(a, b)` returns their constant values (zz = `zz_2d`, 1 for B and Gs of bodies
// whose reference state is unstretched along z).
#pragma once

#include "grid/field.hpp"

#include <array>
#include <string>
#include <vector>

namespace efsi {

struct SymmetricTensorField {
    std::vector<Field> comp; ///< the stored components
    int dim = 3;
    real zz_2d = 1.0;

    /// Component index of (a, b), or -1 when it is not stored (2D zz, xz, yz).
    static int slot(int a, int b, int dim) {
        if (a > b) std::swap(a, b);
        if (dim == 2) {
            if (a == 0 && b == 0) return 0;
            if (a == 1 && b == 1) return 1;
            if (a == 0 && b == 1) return 2;
            return -1;
        }
        if (a == b) return a;      // xx yy zz
        return a == 0 ? 2 + b : 5; // xy=3 xz=4 yz=5
    }
    static int count(int dim) { return dim == 2 ? 3 : 6; }
    /// Names of the stored components, e.g. "B_xy".
    static std::string component_name(const std::string& base, int slot, int dim) {
        static const char* n3[6] = {"xx", "yy", "zz", "xy", "xz", "yz"};
        static const char* n2[3] = {"xx", "yy", "xy"};
        return base + "_" + (dim == 2 ? n2[slot] : n3[slot]);
    }

    real value(int a, int b, const Int3& p) const {
        const int s = slot(a, b, dim);
        if (s >= 0) return comp[s](p);
        return (a == 2 && b == 2) ? zz_2d : 0.0;
    }
};

} // namespace efsi
