/* wg_floquet.c - eigenvalues of a small real matrix (balance + Hessenberg +
 * Francis double-shift QR, after EISPACK balanc/elmhes/hqr) and a small LU
 * solve, for the Floquet multipliers and the Newton steps of wg_shoot.c and
 * wg_cont.c. No allocation: matrices live on the caller's stack (n <= 16). */
#include "wormgear/wg_regime.h"
#include "wormgear/wg_status.h"
#include "internal.h"

#include <math.h>
#include <string.h>

enum { NMAX = 16 };

/* 1-based access into a row-major n x n matrix, as in the classic texts. */
#define A(i, j) a[((i) - 1) * n + ((j) - 1)]

/* Scale rows and columns by powers of 2 so their norms are comparable. */
static void balance(int n, double *a)
{
    const double radix = 2.0, sqrdx = 4.0;
    for (int done = 0; !done;) {
        done = 1;
        for (int i = 1; i <= n; i++) {
            double r = 0.0, c = 0.0;
            for (int j = 1; j <= n; j++)
                if (j != i) {
                    c += fabs(A(j, i));
                    r += fabs(A(i, j));
                }
            if (c == 0.0 || r == 0.0)
                continue;
            double g = r / radix, f = 1.0, s = c + r;
            while (c < g) {
                f *= radix;
                c *= sqrdx;
            }
            g = r * radix;
            while (c > g) {
                f /= radix;
                c /= sqrdx;
            }
            if ((c + r) / f < 0.95 * s) {
                done = 0;
                for (int j = 1; j <= n; j++)
                    A(i, j) /= f;
                for (int j = 1; j <= n; j++)
                    A(j, i) *= f;
            }
        }
    }
}

/* Reduce to upper Hessenberg form by stabilised elimination; entries below
 * the subdiagonal are cleared. */
static void hessenberg(int n, double *a)
{
    for (int m = 2; m < n; m++) {
        double x = 0.0;
        int i = m;
        for (int j = m; j <= n; j++)
            if (fabs(A(j, m - 1)) > fabs(x)) {
                x = A(j, m - 1);
                i = j;
            }
        if (i != m) {
            for (int j = m - 1; j <= n; j++) {
                double t = A(i, j);
                A(i, j) = A(m, j);
                A(m, j) = t;
            }
            for (int j = 1; j <= n; j++) {
                double t = A(j, i);
                A(j, i) = A(j, m);
                A(j, m) = t;
            }
        }
        if (x == 0.0)
            continue;
        for (i = m + 1; i <= n; i++) {
            double y = A(i, m - 1);
            if (y == 0.0)
                continue;
            y /= x;
            A(i, m - 1) = y;
            for (int j = m; j <= n; j++)
                A(i, j) -= y * A(m, j);
            for (int j = 1; j <= n; j++)
                A(j, m) += y * A(j, i);
        }
    }
    for (int i = 3; i <= n; i++)
        for (int j = 1; j < i - 1; j++)
            A(i, j) = 0.0;
}

/* Shift (x, y, w) for the double-shift step; exceptional shifts at 10, 20. */
typedef struct shift {
    double x, y, w;
} shift;

/* Find the start m of the double-shift step on rows l..nn and the first
 * column (p, q, r) of the shifted product. */
static int qr_start(int n, double *a, int l, int nn, const shift *sh, double v[3])
{
    int m;
    double p = 0, q = 0, r = 0;
    for (m = nn - 2; m >= l; m--) {
        double z = A(m, m), rr = sh->x - z, s = sh->y - z;
        p = (rr * s - sh->w) / A(m + 1, m) + A(m, m + 1);
        q = A(m + 1, m + 1) - z - rr - s;
        r = A(m + 2, m + 1);
        s = fabs(p) + fabs(q) + fabs(r);
        p /= s;
        q /= s;
        r /= s;
        if (m == l)
            break;
        double u = fabs(A(m, m - 1)) * (fabs(q) + fabs(r));
        double vv = fabs(p) * (fabs(A(m - 1, m - 1)) + fabs(z) + fabs(A(m + 1, m + 1)));
        if (u + vv == vv)
            break;
    }
    for (int i = m + 2; i <= nn; i++) {
        A(i, i - 2) = 0.0;
        if (i != m + 2)
            A(i, i - 3) = 0.0;
    }
    v[0] = p;
    v[1] = q;
    v[2] = r;
    return m;
}

/* One Francis double-shift QR sweep over rows m..nn (Householder 3x3). */
static void qr_sweep(int n, double *a, int l, int m, int nn, const double v[3])
{
    double p = v[0], q = v[1], r = v[2], x = 0.0, y, z;
    for (int k = m; k <= nn - 1; k++) {
        if (k != m) {
            p = A(k, k - 1);
            q = A(k + 1, k - 1);
            r = k != nn - 1 ? A(k + 2, k - 1) : 0.0;
            if ((x = fabs(p) + fabs(q) + fabs(r)) != 0.0) {
                p /= x;
                q /= x;
                r /= x;
            }
        }
        double s = copysign(sqrt(p * p + q * q + r * r), p);
        if (s == 0.0)
            continue;
        if (k == m) {
            if (l != m)
                A(k, k - 1) = -A(k, k - 1);
        } else {
            A(k, k - 1) = -s * x;
        }
        p += s;
        x = p / s;
        y = q / s;
        z = r / s;
        q /= p;
        r /= p;
        for (int j = k; j <= nn; j++) {
            double t = A(k, j) + q * A(k + 1, j);
            if (k != nn - 1) {
                t += r * A(k + 2, j);
                A(k + 2, j) -= t * z;
            }
            A(k + 1, j) -= t * y;
            A(k, j) -= t * x;
        }
        int mmin = nn < k + 3 ? nn : k + 3;
        for (int i = l; i <= mmin; i++) {
            double t = x * A(i, k) + y * A(i, k + 1);
            if (k != nn - 1) {
                t += z * A(i, k + 2);
                A(i, k + 2) -= t * r;
            }
            A(i, k + 1) -= t * q;
            A(i, k) -= t;
        }
    }
}

/* Eigenvalues of the 2x2 block ending at row nn (shift t added back). */
static void block2(int n, double *a, int nn, double t, double *wr, double *wi)
{
    double x = A(nn, nn), y = A(nn - 1, nn - 1), w = A(nn, nn - 1) * A(nn - 1, nn);
    double p = 0.5 * (y - x), q = p * p + w, z = sqrt(fabs(q));
    x += t;
    if (q >= 0.0) {
        z = p + copysign(z, p);
        wr[nn - 2] = wr[nn - 1] = x + z;
        if (z != 0.0)
            wr[nn - 1] = x - w / z;
        wi[nn - 2] = wi[nn - 1] = 0.0;
    } else {
        wr[nn - 2] = wr[nn - 1] = x + p;
        wi[nn - 2] = z;
        wi[nn - 1] = -z;
    }
}

/* Eigenvalues of an upper Hessenberg matrix (1-based rows, wr/wi 0-based). */
static int hqr(int n, double *a, double *wr, double *wi)
{
    double anorm = 0.0, t = 0.0;
    for (int i = 1; i <= n; i++)
        for (int j = i > 1 ? i - 1 : 1; j <= n; j++)
            anorm += fabs(A(i, j));
    int nn = n, its = 0;
    while (nn >= 1) {
        int l;
        for (l = nn; l >= 2; l--) {
            double s = fabs(A(l - 1, l - 1)) + fabs(A(l, l));
            if (s == 0.0)
                s = anorm;
            if (fabs(A(l, l - 1)) + s == s) {
                A(l, l - 1) = 0.0;
                break;
            }
        }
        if (l == nn) {
            wr[nn - 1] = A(nn, nn) + t;
            wi[nn - 1] = 0.0;
            nn--;
            its = 0;
        } else if (l == nn - 1) {
            block2(n, a, nn, t, wr, wi);
            nn -= 2;
            its = 0;
        } else {
            if (its == 60)
                return WG_ENONFINITE;
            shift sh = {A(nn, nn), A(nn - 1, nn - 1), A(nn, nn - 1) * A(nn - 1, nn)};
            if (its == 10 || its == 20 || its == 40) {
                t += sh.x;
                for (int i = 1; i <= nn; i++)
                    A(i, i) -= sh.x;
                double s = fabs(A(nn, nn - 1)) + fabs(A(nn - 1, nn - 2));
                sh.x = sh.y = 0.75 * s;
                sh.w = -0.4375 * s * s;
            }
            its++;
            double v[3];
            int m = qr_start(n, a, l, nn, &sh, v);
            qr_sweep(n, a, l, m, nn, v);
        }
    }
    return WG_OK;
}

static void sort_by_modulus(int n, double *wr, double *wi)
{
    for (int i = 1; i < n; i++) {
        double r = wr[i], im = wi[i], mod = hypot(r, im);
        int j = i - 1;
        /* ties: larger real part first, then positive imaginary first */
        while (j >= 0 && (hypot(wr[j], wi[j]) < mod ||
                          (hypot(wr[j], wi[j]) == mod &&
                           (wr[j] < r || (wr[j] == r && wi[j] < im))))) {
            wr[j + 1] = wr[j];
            wi[j + 1] = wi[j];
            j--;
        }
        wr[j + 1] = r;
        wi[j + 1] = im;
    }
}

int wg_eig(int n, double *a, double *wr, double *wi)
{
    if (n < 1 || n > NMAX)
        return WG_EINVAL;
    for (int i = 0; i < n * n; i++)
        if (!isfinite(a[i]))
            return WG_ENONFINITE;
    balance(n, a);
    hessenberg(n, a);
    int rc = hqr(n, a, wr, wi);
    if (rc)
        return rc;
    sort_by_modulus(n, wr, wi);
    return WG_OK;
}

int la_solve(int n, double *a, double *r)
{
    for (int k = 1; k <= n; k++) {
        int piv = k;
        for (int i = k + 1; i <= n; i++)
            if (fabs(A(i, k)) > fabs(A(piv, k)))
                piv = i;
        if (A(piv, k) == 0.0 || !isfinite(A(piv, k)))
            return WG_ERANGE;
        if (piv != k) {
            for (int j = 1; j <= n; j++) {
                double t = A(k, j);
                A(k, j) = A(piv, j);
                A(piv, j) = t;
            }
            double t = r[k - 1];
            r[k - 1] = r[piv - 1];
            r[piv - 1] = t;
        }
        for (int i = k + 1; i <= n; i++) {
            double f = A(i, k) / A(k, k);
            for (int j = k; j <= n; j++)
                A(i, j) -= f * A(k, j);
            r[i - 1] -= f * r[k - 1];
        }
    }
    for (int k = n; k >= 1; k--) {
        double s = r[k - 1];
        for (int j = k + 1; j <= n; j++)
            s -= A(k, j) * r[j - 1];
        r[k - 1] = s / A(k, k);
    }
    return WG_OK;
}
