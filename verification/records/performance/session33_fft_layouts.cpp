#include <algorithm>
#include <chrono>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fftw3.h>
#include <sys/mman.h>
#include <vector>
using clk = std::chrono::steady_clock;
using cd = std::complex<double>;
int main(int argc, char** argv) {
    const int N = argc > 1 ? atoi(argv[1]) : 128, nx = N, ny = N, nz = N;
    const int B = argc > 2 ? atoi(argv[2]) : 8;
    const int row = 2 * (nx / 2 + 1), plane = row * ny + 8; // padded plane
    const int crow = row / 2, cplane = plane / 2, nc = nx / 2 + 1;
    size_t tot = size_t(plane) * nz;
    double* a;
    if (getenv("HUGE")) {
        size_t bytes = (tot * 8 + (2u << 20) - 1) / (2u << 20) * (2u << 20);
        posix_memalign((void**)&a, 2u << 20, bytes);
        madvise(a, bytes, MADV_HUGEPAGE);
    } else
        a = fftw_alloc_real(tot);
    double* ref = fftw_alloc_real(tot);
    auto* z = reinterpret_cast<fftw_complex*>(a);
    unsigned flag = getenv("MEAS") ? FFTW_MEASURE : FFTW_ESTIMATE;
    auto fill = [&](double* p) {
        for (size_t i = 0; i < tot; ++i)
            p[i] = 0;
        for (int k = 0; k < nz; ++k)
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i)
                    p[size_t(k) * plane + j * row + i] = std::sin(0.3 * i + 0.7 * j * j + 1.1 * k) +
                                                         0.01 * ((i * 7 + j * 3 + k) % 11);
    };
    // reference plans (as now)
    fftw_iodim along{nx, 1, 1};
    fftw_iodim many[2] = {{nz, plane, cplane}, {ny, row, crow}};
    fftw_plan px = fftw_plan_guru_dft_r2c(1, &along, 2, many, a, z, flag);
    fftw_iodim mb[2] = {{nz, cplane, plane}, {ny, crow, row}};
    fftw_plan qx = fftw_plan_guru_dft_c2r(1, &along, 2, mb, z, a, flag);
    fftw_iodim ay{ny, crow, crow};
    fftw_iodim my[2] = {{nz, cplane, cplane}, {nc, 1, 1}};
    fftw_plan py = fftw_plan_guru_dft(1, &ay, 2, my, z, z, FFTW_FORWARD, flag);
    fftw_plan qy = fftw_plan_guru_dft(1, &ay, 2, my, z, z, FFTW_BACKWARD, flag);
    fftw_iodim az{nz, cplane, cplane};
    fftw_iodim mz[2] = {{ny, crow, crow}, {nc, 1, 1}};
    fftw_plan pz = fftw_plan_guru_dft(1, &az, 2, mz, z, z, FFTW_FORWARD, flag);
    fftw_plan qz = fftw_plan_guru_dft(1, &az, 2, mz, z, z, FFTW_BACKWARD, flag);
    // x pairs: buffer of P pairs, each N complex contiguous
    const int P = 4;
    fftw_complex* xb = fftw_alloc_complex(size_t(P) * nx);
    fftw_iodim xd{nx, 1, 1};
    fftw_iodim xv{P, nx, nx};
    fftw_plan xf = fftw_plan_guru_dft(1, &xd, 1, &xv, xb, xb, FFTW_FORWARD, flag);
    fftw_plan xbk = fftw_plan_guru_dft(1, &xd, 1, &xv, xb, xb, FFTW_BACKWARD, flag);
    auto x_forward = [&]() {
        const int rows = ny * nz;
        auto rowp = [&](int r) { return a + size_t(r / ny) * plane + size_t(r % ny) * row; };
        for (int r0 = 0; r0 < rows; r0 += 2 * P) {
            for (int p = 0; p < P; ++p) {
                const double* r1 = rowp(r0 + 2 * p);
                const double* r2 = rowp(r0 + 2 * p + 1);
                double* c = reinterpret_cast<double*>(xb + size_t(p) * nx);
                for (int n = 0; n < nx; ++n) {
                    c[2 * n] = r1[n];
                    c[2 * n + 1] = r2[n];
                }
            }
            fftw_execute(xf);
            for (int p = 0; p < P; ++p) {
                double* r1 = rowp(r0 + 2 * p);
                double* r2 = rowp(r0 + 2 * p + 1);
                const double* c = reinterpret_cast<const double*>(xb + size_t(p) * nx);
                for (int k = 0; k <= nx / 2; ++k) {
                    const int m = k == 0 ? 0 : nx - k;
                    const double cr = c[2 * k], ci = c[2 * k + 1], mr = c[2 * m], mi = c[2 * m + 1];
                    r1[2 * k] = 0.5 * (cr + mr);
                    r1[2 * k + 1] = 0.5 * (ci - mi);
                    r2[2 * k] = 0.5 * (ci + mi);
                    r2[2 * k + 1] = -0.5 * (cr - mr);
                }
            }
        }
    };
    auto x_backward = [&]() {
        const int rows = ny * nz;
        auto rowp = [&](int r) { return a + size_t(r / ny) * plane + size_t(r % ny) * row; };
        for (int r0 = 0; r0 < rows; r0 += 2 * P) {
            for (int p = 0; p < P; ++p) {
                const double* r1 = rowp(r0 + 2 * p);
                const double* r2 = rowp(r0 + 2 * p + 1);
                double* c = reinterpret_cast<double*>(xb + size_t(p) * nx);
                for (int k = 0; k <= nx / 2; ++k) { // C_k = A_k + i B_k
                    c[2 * k] = r1[2 * k] - r2[2 * k + 1];
                    c[2 * k + 1] = r1[2 * k + 1] + r2[2 * k];
                }
                for (int k = 1; k < (nx + 1) / 2; ++k) { // C_{N-k} = conj(A_k) + i conj(B_k)
                    c[2 * (nx - k)] = r1[2 * k] + r2[2 * k + 1];
                    c[2 * (nx - k) + 1] = -r1[2 * k + 1] + r2[2 * k];
                }
            }
            fftw_execute(xbk);
            for (int p = 0; p < P; ++p) {
                double* r1 = rowp(r0 + 2 * p);
                double* r2 = rowp(r0 + 2 * p + 1);
                const double* c = reinterpret_cast<const double*>(xb + size_t(p) * nx);
                for (int n = 0; n < nx; ++n) {
                    r1[n] = c[2 * n];
                    r2[n] = c[2 * n + 1];
                }
            }
        }
    };
    // z buffered: B complex per level, interleaved layout buf[k*B + t]
    fftw_complex* zb = fftw_alloc_complex(size_t(B) * nz);
    fftw_iodim zd{nz, B, B};
    fftw_iodim zv{B, 1, 1};
    fftw_plan zf = fftw_plan_guru_dft(1, &zd, 1, &zv, zb, zb, FFTW_FORWARD, flag);
    fftw_plan zbk = fftw_plan_guru_dft(1, &zd, 1, &zv, zb, zb, FFTW_BACKWARD, flag);
    const int rem = nc % B;
    fftw_complex* zr = fftw_alloc_complex(size_t(std::max(rem, 1)) * nz);
    fftw_iodim zdr{nz, rem, rem};
    fftw_iodim zvr{rem, 1, 1};
    fftw_plan zfr =
        rem ? fftw_plan_guru_dft(1, &zdr, 1, &zvr, zr, zr, FFTW_FORWARD, flag) : nullptr;
    fftw_plan zbr =
        rem ? fftw_plan_guru_dft(1, &zdr, 1, &zvr, zr, zr, FFTW_BACKWARD, flag) : nullptr;
    auto z_pass = [&](bool fwd) {
        for (int j = 0; j < ny; ++j)
            for (int i0 = 0; i0 < nc; i0 += B) {
                const int w = std::min(B, nc - i0);
                fftw_complex* buf = w == B ? zb : zr;
                for (int k = 0; k < nz; ++k)
                    memcpy(buf + size_t(k) * w, z + size_t(k) * cplane + size_t(j) * crow + i0,
                           w * sizeof(fftw_complex));
                fftw_execute(w == B ? (fwd ? zf : zbk) : (fwd ? zfr : zbr));
                for (int k = 0; k < nz; ++k)
                    memcpy(z + size_t(k) * cplane + size_t(j) * crow + i0, buf + size_t(k) * w,
                           w * sizeof(fftw_complex));
            }
    };
    fftw_complex* yb = fftw_alloc_complex(size_t(B) * ny);
    fftw_iodim yd{ny, B, B};
    fftw_iodim yv{B, 1, 1};
    fftw_plan yf = fftw_plan_guru_dft(1, &yd, 1, &yv, yb, yb, FFTW_FORWARD, flag);
    fftw_plan ybk = fftw_plan_guru_dft(1, &yd, 1, &yv, yb, yb, FFTW_BACKWARD, flag);
    fftw_complex* yr = fftw_alloc_complex(size_t(std::max(rem, 1)) * ny);
    fftw_iodim ydr{ny, rem, rem};
    fftw_iodim yvr{rem, 1, 1};
    fftw_plan yfr =
        rem ? fftw_plan_guru_dft(1, &ydr, 1, &yvr, yr, yr, FFTW_FORWARD, flag) : nullptr;
    fftw_plan ybr =
        rem ? fftw_plan_guru_dft(1, &ydr, 1, &yvr, yr, yr, FFTW_BACKWARD, flag) : nullptr;
    auto y_pass = [&](bool fwd) {
        for (int k = 0; k < nz; ++k)
            for (int i0 = 0; i0 < nc; i0 += B) {
                const int w = std::min(B, nc - i0);
                fftw_complex* buf = w == B ? yb : yr;
                for (int j = 0; j < ny; ++j)
                    memcpy(buf + size_t(j) * w, z + size_t(k) * cplane + size_t(j) * crow + i0,
                           w * sizeof(fftw_complex));
                fftw_execute(w == B ? (fwd ? yf : ybk) : (fwd ? yfr : ybr));
                for (int j = 0; j < ny; ++j)
                    memcpy(z + size_t(k) * cplane + size_t(j) * crow + i0, buf + size_t(j) * w,
                           w * sizeof(fftw_complex));
            }
    };
    // correctness: forward spectra equal
    fill(a);
    fftw_execute(px);
    fftw_execute(py);
    fftw_execute(pz);
    memcpy(ref, a, tot * 8);
    fill(a);
    x_forward();
    fftw_execute(py);
    z_pass(true);
    double md = 0, mx = 0;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < 2 * nc; ++i) {
                size_t q = size_t(k) * plane + j * row + i;
                md = std::max(md, std::abs(a[q] - ref[q]));
                mx = std::max(mx, std::abs(ref[q]));
            }
    printf("forward max diff %.3e (max %.3e)\n", md, mx);
    fftw_execute(qz);
    fftw_execute(qy);
    x_backward(); // back: should give N^3 * input
    fill(ref);
    md = 0;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                size_t q = size_t(k) * plane + j * row + i;
                md = std::max(md, std::abs(a[q] / double(nx) / ny / nz - ref[q]));
            }
    printf("roundtrip max diff %.3e\n", md);
    auto time = [&](const char* name, auto f) {
        fill(a);
        f();
        double best = 1e9;
        for (int r = 0; r < 7; ++r) {
            auto t0 = clk::now();
            f();
            best = std::min(best, std::chrono::duration<double>(clk::now() - t0).count());
        }
        printf("%-30s: %.2f ms\n", name, best * 1e3);
    };
    time("now y first", [&] {
        fftw_execute(py);
        fftw_execute(qy);
    });
    time("now: x+y+z fwd+bwd", [&] {
        fftw_execute(px);
        fftw_execute(py);
        fftw_execute(pz);
        fftw_execute(qz);
        fftw_execute(qy);
        fftw_execute(qx);
    });
    time("now x", [&] {
        fftw_execute(px);
        fftw_execute(qx);
    });
    time("pairs x", [&] {
        x_forward();
        x_backward();
    });
    time("now y", [&] {
        fftw_execute(py);
        fftw_execute(qy);
    });
    time("buffered y", [&] {
        y_pass(true);
        y_pass(false);
    });
    time("now z", [&] {
        fftw_execute(pz);
        fftw_execute(qz);
    });
    time("buffered z", [&] {
        z_pass(true);
        z_pass(false);
    });
    time("new: x+y+z", [&] {
        x_forward();
        fftw_execute(py);
        z_pass(true);
        z_pass(false);
        fftw_execute(qy);
        x_backward();
    });
}
