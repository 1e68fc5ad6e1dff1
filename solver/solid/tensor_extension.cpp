#include "solid/tensor_extension.hpp"

#include <array>

namespace efsi {

void TensorExtension::apply(Body& body) {
    if (body.patch().empty() || threshold_ <= 0 || body.tensor().comp.empty()) return;
    const GlobalGrid& g = halos_.decomposition().grid();
    const int dim = g.dim;
    const Field& phi = body.phi();
    SymmetricTensorField& B = body.tensor();
    const int ncomp = int(B.comp.size());
    if (level_.data().empty() || level_.begin() != phi.begin() || level_.cells() != phi.cells())
        level_ = Field::on_patch("extension_level", Location::Cell, phi.begin(), phi.cells(), dim);
    const Box cells = phi.owned();
    for_each_in(cells, [&](int i, int j, int k) {
        const real v = phi(i, j, k);
        const bool known = v >= threshold_ && (!two_sided_ || v <= 1 - threshold_);
        level_(i, j, k) = known ? 0.0 : -1.0;
    });
    halos_.fill(level_, body.patch());
    for (Field& c : B.comp) // the transport leaves the halos at the old B
        halos_.fill(c, body.patch());
    const int kz = dim == 3 ? 1 : 0;
    for (int layer = 1; layer <= layers_; ++layer) {
        for_each_in(cells, [&](int i, int j, int k) {
            if (level_(i, j, k) >= 0) return;
            const Int3 p{i, j, k};
            std::array<real, 6> sum{};
            int count = 0;
            for (int c = -kz; c <= kz; ++c)
                for (int b = -1; b <= 1; ++b)
                    for (int a = -1; a <= 1; ++a) {
                        const real lq = level_(i + a, j + b, k + c);
                        if (lq < 0 || lq >= layer) continue; // unknown, or set in this layer
                        for (int s = 0; s < ncomp; ++s)
                            sum[s] += B.comp[s](i + a, j + b, k + c);
                        ++count;
                    }
            if (count == 0) return;
            for (int s = 0; s < ncomp; ++s)
                B.comp[s](p) = sum[s] / count;
            level_(p) = layer;
        });
        halos_.fill(level_, body.patch());
        if (layer < layers_)
            for (Field& c : B.comp)
                halos_.fill(c, body.patch());
    }
    // Cells never reached (more than `layers` cells from any solid core): B = I. They hold
    // at most VOF residues (phi ~ 1e-10), whose B would otherwise keep growing in the
    // fluid's shear.
    for_each_in(cells, [&](int i, int j, int k) {
        if (level_(i, j, k) >= 0) return;
        for (int a = 0; a < 3; ++a)
            for (int b = a; b < 3; ++b) {
                const int s = SymmetricTensorField::slot(a, b, dim);
                if (s >= 0) B.comp[s](i, j, k) = a == b ? 1.0 : 0.0;
            }
    });
    for (Field& c : B.comp)
        halos_.fill(c, body.patch());
}

} // namespace efsi
