/* kern_batch.h - the batched run (wg_kbatch, lib/internal.h) of the full
 * path: part of kern_tmpl.h's template, included by it for AVX-512 only
 * (KW == 8, where vb holds eight doubles) after the kernel's own helpers,
 * which it uses (vsplat, vdz, vabs). Not a header of its own. */
#if KW != 8
#error "kern_batch.h: only inside kern_tmpl.h with KW == 8"
#endif

/* The same arithmetic as rk4_full_t, frun_check and kloc_accept, in the
 * same order, with every scalar of one run a lane of a vector of eight
 * runs (KW == 8: vb holds eight doubles). */

typedef struct bst {
    vb q[6], v[6], s, vs;
} bst;

INLINE vb bld(const double *p) { return (vb)_mm512_load_pd(p); }
INLINE void bsto(double *p, vb x) { _mm512_store_pd(p, (__m512d)x); }
INLINE vb bmin(vb a, vb b) { return (vb)_mm512_min_pd((__m512d)a, (__m512d)b); }
INLINE vb bmax(vb a, vb b) { return (vb)_mm512_max_pd((__m512d)a, (__m512d)b); }
/* lanes in m from a, the others from b */
INLINE vb bsel(__mmask8 m, vb a, vb b)
{
    return (vb)_mm512_mask_blend_pd(m, (__m512d)b, (__m512d)a);
}
/* ((p0 + p2) + p4) + ((p1 + p3) + p5): hsumb's order */
INLINE vb bsum6(const vb p[6]) { return ((p[0] + p[2]) + p[4]) + ((p[1] + p[3]) + p[5]); }
INLINE __mmask8 bcmpm(vb a, vb b, const int op)
{
    return _mm512_cmp_pd_mask((__m512d)a, (__m512d)b, op);
}

/* The three excitation entries of each lane's step i (table[2k .. 2k+2],
 * twelve doubles in a row) as twelve vectors: kp, te, dte, fx of each. */
INLINE void bexc(const wg_exc *const ep[8], uint64_t i, vb kp[3], vb te[3], vb dte[3],
                 vb fx[3])
{
    __m512d r[8], t0[8], t1[8], f[8];
    __m256d u[8];
#pragma GCC unroll 8
    for (int l = 0; l < 8; l++) {
        const double *p = &ep[l][2 * i].kp;
        r[l] = _mm512_loadu_pd(p);
        u[l] = _mm256_loadu_pd(p + 8);
    }
    /* r[l] = entries 2k, 2k+1 of lane l: transpose 8 x 8 */
#pragma GCC unroll 4
    for (int l = 0; l < 8; l += 2) {
        t0[l] = _mm512_unpacklo_pd(r[l], r[l + 1]);
        t0[l + 1] = _mm512_unpackhi_pd(r[l], r[l + 1]);
    }
#pragma GCC unroll 2
    for (int l = 0; l < 8; l += 4) {
        t1[l] = _mm512_shuffle_f64x2(t0[l], t0[l + 2], 0x88);
        t1[l + 1] = _mm512_shuffle_f64x2(t0[l + 1], t0[l + 3], 0x88);
        t1[l + 2] = _mm512_shuffle_f64x2(t0[l], t0[l + 2], 0xdd);
        t1[l + 3] = _mm512_shuffle_f64x2(t0[l + 1], t0[l + 3], 0xdd);
    }
#pragma GCC unroll 4
    for (int j = 0; j < 4; j++) {
        f[j] = _mm512_shuffle_f64x2(t1[j], t1[j + 4], 0x88);
        f[j + 4] = _mm512_shuffle_f64x2(t1[j], t1[j + 4], 0xdd);
    }
    kp[0] = (vb)f[0], te[0] = (vb)f[1], dte[0] = (vb)f[2], fx[0] = (vb)f[3];
    kp[1] = (vb)f[4], te[1] = (vb)f[5], dte[1] = (vb)f[6], fx[1] = (vb)f[7];
    /* u[l] = entry 2k+2 of lane l: transpose 8 x 4 */
    __m512d w[4];
#pragma GCC unroll 4
    for (int l = 0; l < 4; l++)
        w[l] = _mm512_insertf64x4(_mm512_castpd256_pd512(u[l]), u[l + 4], 1);
    __m512d a0 = _mm512_unpacklo_pd(w[0], w[1]), a1 = _mm512_unpackhi_pd(w[0], w[1]);
    __m512d a2 = _mm512_unpacklo_pd(w[2], w[3]), a3 = _mm512_unpackhi_pd(w[2], w[3]);
    /* lanes in the order 0 1 4 5 2 3 6 7: put them back */
    const __m512i perm = _mm512_set_epi64(7, 6, 3, 2, 5, 4, 1, 0);
    kp[2] = (vb)_mm512_permutexvar_pd(perm, _mm512_shuffle_f64x2(a0, a2, 0x88));
    te[2] = (vb)_mm512_permutexvar_pd(perm, _mm512_shuffle_f64x2(a1, a3, 0x88));
    dte[2] = (vb)_mm512_permutexvar_pd(perm, _mm512_shuffle_f64x2(a0, a2, 0xdd));
    fx[2] = (vb)_mm512_permutexvar_pd(perm, _mm512_shuffle_f64x2(a1, a3, 0xdd));
}

/* One stage of eight runs: stage_full lane-wise. */
INLINE void bstage(const wg_kbatch *restrict B, vb kp, vb te, vb dte, vb fx, const vb q[6],
                   const vb v[6], vb vs, vb X, vb V, vb acc[6], vb *as6, vb *cacc,
                   const int LOCK, const int BJ, const int MB, const int KA, const int EM)
{
    vb xn = X, dxn = V;
    if (EM) {
        xn -= te;
        dxn += dte;
    }
    vb g = !MB ? xn : LOCK ? bld(B->w0) * xn - bld(B->zc0) : vdz(xn, bld(B->b));
    vb F = bld(B->dp) * dxn + (KA ? kp * g : g);
    vb pb[6];
#pragma GCC unroll 6
    for (int b = 0; b < 6; b++) {
        vb gb = !BJ ? q[b] : LOCK ? bld(B->w[b]) * q[b] - bld(B->zc[b]) : vdz(q[b], bld(B->bj));
        vb base = bld(B->nd[b]) * v[b] - bld(B->k[b]) * gb; /* (-d) v == -(d v) exactly */
        pb[b] = bld(B->cd[b]) * v[b] + bld(B->ck[b]) * gb;
        acc[b] = base - bld(B->m[b]) * F;
    }
    vb P = (fx - bld(B->ds) * vs) - bsum6(pb);
    *as6 = (fx - F) - bld(B->ds) * vs;
    *cacc = P - bld(B->M) * F;
}

/* One RK4 step of eight runs: rk4_full_t lane-wise. */
INLINE bst brk4(const wg_kbatch *restrict B, const vb kp[3], const vb te[3], const vb dte[3],
                const vb fx[3], vb h, bst y0, const int LOCK, const int BJ, const int MB,
                const int KA, const int EM)
{
    vb q[6], v[6], acc[6], sq[6], sv[6], pq[6], pv[6];
    static const double wt[4] = {1.0, 2.0, 2.0, 1.0};
    const vb half = vsplat(0.5) * h;
#pragma GCC unroll 6
    for (int b = 0; b < 6; b++) {
        q[b] = y0.q[b];
        v[b] = y0.v[b];
        pq[b] = bld(B->c[b]) * y0.q[b];
        pv[b] = bld(B->c[b]) * y0.v[b];
        sq[b] = sv[b] = vsplat(0.0);
    }
    vb X0 = bsum6(pq) + y0.s, V0 = bsum6(pv) + y0.vs;
    vb X = X0, V = V0, vs = y0.vs, ssv = vsplat(0.0), sas = vsplat(0.0);
#pragma GCC unroll 4
    for (int j = 0; j < 4; j++) {
        const int ei = (j + 1) / 2;
        vb as6, cacc;
        bstage(B, kp[ei], te[ei], dte[ei], fx[ei], q, v, vs, X, V, acc, &as6, &cacc, LOCK, BJ,
               MB, KA, EM);
        vb w = vsplat(wt[j]);
#pragma GCC unroll 6
        for (int b = 0; b < 6; b++) {
            sq[b] += w * v[b];
            sv[b] += w * acc[b];
        }
        ssv += w * vs;
        sas += w * as6;
        if (j == 3)
            continue;
        vb a = j == 2 ? h : half;
        vb Vn = V0 + a * cacc;
        X = X0 + a * V;
        V = Vn;
#pragma GCC unroll 6
        for (int b = 0; b < 6; b++) {
            vb qn = y0.q[b] + a * v[b];
            v[b] = y0.v[b] + a * acc[b];
            q[b] = qn;
        }
        vs = y0.vs + a * as6;
    }
    bst y1;
    vb h6 = h / vsplat(6.0);
#pragma GCC unroll 6
    for (int b = 0; b < 6; b++) {
        y1.q[b] = y0.q[b] + h6 * sq[b];
        y1.v[b] = y0.v[b] + h6 * sv[b];
    }
    y1.s = y0.s + h6 * ssv;
    y1.vs = y0.vs + h6 * sas;
    return y1;
}

/* The batch's loop (wg_kbatch_fn): plain steps of every lane until a lane
 * in B->active refuses one (its trial written) or has taken its
 * lim_steps. */
INLINE unsigned run_batch(wg_kbatch *restrict B, const int LOCK, const int BJ, const int MB,
                          const int KA, const int EM)
{
    const unsigned act = B->active & 0xffu;
    uint64_t nmax = UINT64_MAX;
    int first = __builtin_ctz(act);
    const wg_exc *ep[8];
    for (int l = 0; l < 8; l++) {
        int in = (act >> l) & 1u;
        ep[l] = in ? B->ep[l] : B->ep[first]; /* a lane left out reads in bounds */
        if (in && B->lim_steps[l] < nmax)
            nmax = B->lim_steps[l];
    }
    bst y;
#pragma GCC unroll 6
    for (int b = 0; b < 6; b++) {
        y.q[b] = bld(B->q[b]);
        y.v[b] = bld(B->v[b]);
    }
    y.s = bld(B->s), y.vs = bld(B->vs);
    vb xn = bld(B->xn), dxn = bld(B->dxn), tau = bld(B->tau), tc = bld(B->tc);
    vb mn = bld(B->mn), mx = bld(B->mx);
    const vb h = bld(B->h), zero = vsplat(0.0);
    unsigned refused = 0;
    uint64_t i, step[8] = {0}; /* step: the refusal's step, where taken */
    for (i = 0; i < nmax; i++) {
        vb kp[3], te[3], dte[3], fx[3];
        bexc(ep, i, kp, te, dte, fx);
        bst z = brk4(B, kp, te, dte, fx, h, y, LOCK, BJ, MB, KA, EM);
        /* frun_check: the mesh contact in ct_contacts' order, the bounds */
        vb xs = -te[2], dxs = dte[2];
#pragma GCC unroll 6
        for (int b = 0; b < 6; b++) {
            xs += bld(B->c[b]) * z.q[b];
            dxs += bld(B->c[b]) * z.v[b];
        }
        xs += z.s;
        dxs += z.vs;
        const vb lim = bld(B->lim);
        __mmask8 ok = bcmpm(vabs(z.s), lim, _CMP_LT_OQ) & bcmpm(vabs(z.vs), lim, _CMP_LT_OQ) &
                      bcmpm(xs, bld(B->mlo), _CMP_GE_OQ) & bcmpm(xs, bld(B->mhi), _CMP_LE_OQ);
#pragma GCC unroll 6
        for (int b = 0; b < 6; b++)
            ok &= bcmpm(z.q[b], bld(B->lo[b]), _CMP_GE_OQ) &
                  bcmpm(z.q[b], bld(B->hi[b]), _CMP_LE_OQ) &
                  bcmpm(vabs(z.v[b]), lim, _CMP_LT_OQ);
        /* kloc_accept lane-wise: Kahan time, an extremum inside the step
         * (rare: lane by lane), the period's extrema. A lane that refuses
         * the step keeps its state; the others take it, and the loop ends. */
        const __mmask8 rf = ~ok & act, acc = rf ? (__mmask8)~rf : 0xff;
        vb dt = h - tc, t = tau + dt, ntc = (t - tau) - dt;
        __mmask8 turn = (bcmpm(dxn, zero, _CMP_LT_OQ) ^ bcmpm(dxs, zero, _CMP_LT_OQ)) & acc;
        if (__builtin_expect(turn != 0, 0)) {
            for (int l = 0; l < 8; l++)
                if ((turn >> l) & 1u) {
                    double a = mn[l], c = mx[l];
                    herm_turn(xn[l], xs[l], dxn[l], dxs[l], h[l], &a, &c);
                    mn[l] = a, mx[l] = c;
                }
        }
        if (__builtin_expect(rf == 0, 1)) {
            tc = ntc;
            tau = t;
            mn = bmin(mn, xs);
            mx = bmax(mx, xs);
            xn = xs;
            dxn = dxs;
            y = z;
            continue;
        }
        refused = rf;
        for (int l = 0; l < 8; l++) /* frun_refuse: the step as kst_store writes it */
            if ((refused >> l) & 1u) {
                double *tr = B->trial[l];
                for (int b = 0; b < 6; b++) {
                    tr[b] = z.q[b][l];
                    tr[7 + b] = z.v[b][l];
                }
                tr[6] = z.s[l];
                tr[13] = z.vs[l];
            }
        tc = bsel(acc, ntc, tc);
        tau = bsel(acc, t, tau);
        mn = bsel(acc, bmin(mn, xs), mn);
        mx = bsel(acc, bmax(mx, xs), mx);
        xn = bsel(acc, xs, xn);
        dxn = bsel(acc, dxs, dxn);
#pragma GCC unroll 6
        for (int b = 0; b < 6; b++) {
            y.q[b] = bsel(acc, z.q[b], y.q[b]);
            y.v[b] = bsel(acc, z.v[b], y.v[b]);
        }
        y.s = bsel(acc, z.s, y.s);
        y.vs = bsel(acc, z.vs, y.vs);
        for (int l = 0; l < 8; l++)
            step[l] += (acc >> l) & 1u;
        break;
    }
#pragma GCC unroll 6
    for (int b = 0; b < 6; b++) {
        bsto(B->q[b], y.q[b]);
        bsto(B->v[b], y.v[b]);
    }
    bsto(B->s, y.s), bsto(B->vs, y.vs);
    bsto(B->xn, xn), bsto(B->dxn, dxn), bsto(B->tau, tau), bsto(B->tc, tc);
    bsto(B->mn, mn), bsto(B->mx, mx);
    B->refused = refused;
    unsigned stop = refused;
    for (int l = 0; l < 8; l++) {
        uint64_t m = i + step[l];
        B->ran[l] = m;
        B->lim_steps[l] = B->lim_steps[l] > m ? B->lim_steps[l] - m : 0;
        B->ep[l] = ep[l] + 2 * m;
        if (((act >> l) & 1u) && B->lim_steps[l] == 0)
            stop |= 1u << l;
    }
    return stop;
}
