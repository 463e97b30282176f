/* kern_batch.h - the batched run (wg_kbatch, lib/internal.h) of the full
 * path: part of kern_tmpl.h's template, included by it for AVX2 (KW == 4)
 * and AVX-512 (KW == 8) after the kernel's own helpers, which it uses
 * (vsplat, vdz, vabs). Not a header of its own. */
#if KW != 4 && KW != 8
#error "kern_batch.h: only inside kern_tmpl.h with KW == 4 or 8"
#endif

/* The same arithmetic as rk4_full_t, frun_check and kloc_accept, in the
 * same order, with every scalar of one run a lane of a vector (vb: KW
 * runs). The batch's KB_LANES lanes are BG groups of KW: one vector on
 * AVX-512, two on AVX2, whose steps are independent chains the CPU
 * overlaps; the upper group is not computed while none of its lanes is
 * active. A lane mask is an unsigned, bit l for lane l of the batch. */
#define BG (KB_LANES / KW)

typedef struct bst {
    vb q[6], v[6], s, vs;
} bst;

#if KW == 8
INLINE vb bld(const double *p) { return (vb)_mm512_load_pd(p); }
INLINE void bsto(double *p, vb x) { _mm512_store_pd(p, (__m512d)x); }
INLINE vb bmin(vb a, vb b) { return (vb)_mm512_min_pd((__m512d)a, (__m512d)b); }
INLINE vb bmax(vb a, vb b) { return (vb)_mm512_max_pd((__m512d)a, (__m512d)b); }
/* lanes in m from a, the others from b */
INLINE vb bsel(unsigned m, vb a, vb b)
{
    return (vb)_mm512_mask_blend_pd((__mmask8)m, (__m512d)b, (__m512d)a);
}
INLINE unsigned bcmpm(vb a, vb b, const int op)
{
    return _mm512_cmp_pd_mask((__m512d)a, (__m512d)b, op);
}
/* a & b of two lane masks, kept as written: GCC would otherwise make a
 * chain of ANDed compares one masked compare after another */
INLINE unsigned band(unsigned a, unsigned b)
{
    return _kand_mask16((__mmask16)a, (__mmask16)b);
}
#else
INLINE vb bld(const double *p) { return (vb)_mm256_load_pd(p); }
INLINE void bsto(double *p, vb x) { _mm256_store_pd(p, (__m256d)x); }
INLINE vb bmin(vb a, vb b) { return (vb)_mm256_min_pd((__m256d)a, (__m256d)b); }
INLINE vb bmax(vb a, vb b) { return (vb)_mm256_max_pd((__m256d)a, (__m256d)b); }
INLINE vb bsel(unsigned m, vb a, vb b)
{
    const vbi k = {-(long long)(m & 1u), -(long long)((m >> 1) & 1u),
                   -(long long)((m >> 2) & 1u), -(long long)((m >> 3) & 1u)};
    return (vb)(((vbi)a & k) | ((vbi)b & ~k));
}
INLINE unsigned bcmpm(vb a, vb b, const int op)
{
    return (unsigned)_mm256_movemask_pd(_mm256_cmp_pd((__m256d)a, (__m256d)b, op));
}
INLINE unsigned band(unsigned a, unsigned b) { return a & b; }
#endif
/* ((p0 + p2) + p4) + ((p1 + p3) + p5): hsumb's order */
INLINE vb bsum6(const vb p[6]) { return ((p[0] + p[2]) + p[4]) + ((p[1] + p[3]) + p[5]); }

/* The three excitation entries of each lane's step i (table[2k .. 2k+2],
 * twelve doubles in a row) as twelve vectors: kp, te, dte, fx of each;
 * ep: the group's KW lanes. */
INLINE void bexc(const wg_exc *const ep[KW], uint64_t i, vb kp[3], vb te[3], vb dte[3],
                 vb fx[3])
{
#if KW == 8
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
#else
    /* entry e of the four lanes, rows kp te dte fx: transpose 4 x 4 */
#pragma GCC unroll 3
    for (int e = 0; e < 3; e++) {
        __m256d r[4];
#pragma GCC unroll 4
        for (int l = 0; l < 4; l++)
            r[l] = _mm256_loadu_pd(&ep[l][2 * i + (uint64_t)e].kp);
        __m256d t0 = _mm256_unpacklo_pd(r[0], r[1]), t1 = _mm256_unpackhi_pd(r[0], r[1]);
        __m256d t2 = _mm256_unpacklo_pd(r[2], r[3]), t3 = _mm256_unpackhi_pd(r[2], r[3]);
        kp[e] = (vb)_mm256_permute2f128_pd(t0, t2, 0x20);
        te[e] = (vb)_mm256_permute2f128_pd(t1, t3, 0x20);
        dte[e] = (vb)_mm256_permute2f128_pd(t0, t2, 0x31);
        fx[e] = (vb)_mm256_permute2f128_pd(t1, t3, 0x31);
    }
#endif
}

/* One stage of the KW runs from lane o: stage_full lane-wise. */
INLINE void bstage(const wg_kbatch *restrict B, int o, vb kp, vb te, vb dte, vb fx, const vb q[6],
                   const vb v[6], vb vs, vb X, vb V, vb acc[6], vb *as6, vb *cacc,
                   const int LOCK, const int BJ, const int MB, const int KA, const int EM)
{
    vb xn = X, dxn = V;
    if (EM) {
        xn -= te;
        dxn += dte;
    }
    vb g = !MB ? xn : LOCK ? bld(B->w0 + o) * xn - bld(B->zc0 + o) : vdz(xn, bld(B->b + o));
    vb F = bld(B->dp + o) * dxn + (KA ? kp * g : g);
    vb pb[6];
#pragma GCC unroll 6
    for (int b = 0; b < 6; b++) {
        vb gb = !BJ   ? q[b]
                : LOCK ? bld(B->w[b] + o) * q[b] - bld(B->zc[b] + o)
                       : vdz(q[b], bld(B->bj + o));
        vb base = bld(B->nd[b] + o) * v[b] - bld(B->k[b] + o) * gb; /* (-d) v == -(d v) exactly */
        pb[b] = bld(B->cd[b] + o) * v[b] + bld(B->ck[b] + o) * gb;
        acc[b] = base - bld(B->m[b] + o) * F;
    }
    vb P = (fx - bld(B->ds + o) * vs) - bsum6(pb);
    *as6 = (fx - F) - bld(B->ds + o) * vs;
    *cacc = P - bld(B->M + o) * F;
}

/* One RK4 step of the KW runs from lane o: rk4_full_t lane-wise. */
INLINE bst brk4(const wg_kbatch *restrict B, int o, const vb kp[3], const vb te[3], const vb dte[3],
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
        pq[b] = bld(B->c[b] + o) * y0.q[b];
        pv[b] = bld(B->c[b] + o) * y0.v[b];
        sq[b] = sv[b] = vsplat(0.0);
    }
    vb X0 = bsum6(pq) + y0.s, V0 = bsum6(pv) + y0.vs;
    vb X = X0, V = V0, vs = y0.vs, ssv = vsplat(0.0), sas = vsplat(0.0);
#pragma GCC unroll 4
    for (int j = 0; j < 4; j++) {
        const int ei = (j + 1) / 2;
        vb as6, cacc;
        bstage(B, o, kp[ei], te[ei], dte[ei], fx[ei], q, v, vs, X, V, acc, &as6, &cacc, LOCK, BJ,
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
    const unsigned all = (1u << KB_LANES) - 1, act = B->active & all;
    uint64_t nmax = UINT64_MAX;
    int first = __builtin_ctz(act);
    const wg_exc *ep[KB_LANES];
    for (int l = 0; l < KB_LANES; l++) {
        int in = (act >> l) & 1u;
        ep[l] = in ? B->ep[l] : B->ep[first]; /* a lane left out reads in bounds */
        if (in && B->lim_steps[l] < nmax)
            nmax = B->lim_steps[l];
    }
    /* the groups up to the last with an active lane are computed */
    const int ng = BG == 1 || !(act >> KW) ? 1 : BG;
    const unsigned gm = (1u << KW) - 1;
    bst y[BG];
    vb xn[BG], dxn[BG], tau[BG], tc[BG], mn[BG], mx[BG], h[BG];
#pragma GCC unroll 2
    for (int g = 0; g < BG; g++) {
        const int o = g * KW;
#pragma GCC unroll 6
        for (int b = 0; b < 6; b++) {
            y[g].q[b] = bld(B->q[b] + o);
            y[g].v[b] = bld(B->v[b] + o);
        }
        y[g].s = bld(B->s + o), y[g].vs = bld(B->vs + o);
        xn[g] = bld(B->xn + o), dxn[g] = bld(B->dxn + o);
        tau[g] = bld(B->tau + o), tc[g] = bld(B->tc + o);
        mn[g] = bld(B->mn + o), mx[g] = bld(B->mx + o), h[g] = bld(B->h + o);
    }
    const vb zero = vsplat(0.0);
    unsigned refused = 0;
    uint64_t i, step[KB_LANES] = {0}; /* step: the refusal's step, where taken */
    for (i = 0; i < nmax; i++) {
        bst z[BG];
        vb xs[BG], dxs[BG];
        unsigned ok = all;
#pragma GCC unroll 2
        for (int g = 0; g < ng; g++) {
            const int o = g * KW;
            vb kp[3], te[3], dte[3], fx[3];
            bexc(&ep[o], i, kp, te, dte, fx);
            z[g] = brk4(B, o, kp, te, dte, fx, h[g], y[g], LOCK, BJ, MB, KA, EM);
            /* frun_check: the mesh contact in ct_contacts' order, the bounds */
            vb x = -te[2], dx = dte[2];
#pragma GCC unroll 6
            for (int b = 0; b < 6; b++) {
                x += bld(B->c[b] + o) * z[g].q[b];
                dx += bld(B->c[b] + o) * z[g].v[b];
            }
            x += z[g].s;
            dx += z[g].vs;
            xs[g] = x, dxs[g] = dx;
            /* 22 tests, each lane's: ANDed as a tree (band). As one
             * chain of masked compares they cost the AVX-512 batch 12-15 %
             * of its step on a Zen 5 (docs/performance.md, "A Zen 5 EPYC
             * with AVX-512") */
            const vb lim = bld(B->lim + o);
            unsigned kb[7];
#pragma GCC unroll 6
            for (int b = 0; b < 6; b++)
                kb[b] = band(band(bcmpm(z[g].q[b], bld(B->lo[b] + o), _CMP_GE_OQ),
                                  bcmpm(z[g].q[b], bld(B->hi[b] + o), _CMP_LE_OQ)),
                             bcmpm(vabs(z[g].v[b]), lim, _CMP_LT_OQ));
            kb[6] = band(band(bcmpm(vabs(z[g].s), lim, _CMP_LT_OQ),
                              bcmpm(vabs(z[g].vs), lim, _CMP_LT_OQ)),
                         band(bcmpm(x, bld(B->mlo + o), _CMP_GE_OQ),
                              bcmpm(x, bld(B->mhi + o), _CMP_LE_OQ)));
            const unsigned k = band(band(band(kb[0], kb[1]), band(kb[2], kb[3])),
                                    band(band(kb[4], kb[5]), kb[6]));
            ok &= ~(gm << o) | (k << o);
        }
        /* kloc_accept lane-wise: Kahan time, an extremum inside the step
         * (rare: lane by lane), the period's extrema. A lane that refuses
         * the step keeps its state; the others take it, and the loop ends. */
        const unsigned rf = ~ok & act, acc = rf ? ~rf & all : all;
        vb t[BG], ntc[BG];
#pragma GCC unroll 2
        for (int g = 0; g < ng; g++) {
            const int o = g * KW;
            vb dt = h[g] - tc[g];
            t[g] = tau[g] + dt;
            ntc[g] = (t[g] - tau[g]) - dt;
            unsigned turn =
                (bcmpm(dxn[g], zero, _CMP_LT_OQ) ^ bcmpm(dxs[g], zero, _CMP_LT_OQ)) &
                (acc >> o) & gm;
            if (__builtin_expect(turn != 0, 0)) {
                for (int l = 0; l < KW; l++)
                    if ((turn >> l) & 1u) {
                        double a = mn[g][l], c = mx[g][l];
                        herm_turn(xn[g][l], xs[g][l], dxn[g][l], dxs[g][l], h[g][l], &a, &c);
                        mn[g][l] = a, mx[g][l] = c;
                    }
            }
        }
        if (__builtin_expect(rf == 0, 1)) {
#pragma GCC unroll 2
            for (int g = 0; g < ng; g++) {
                tc[g] = ntc[g];
                tau[g] = t[g];
                mn[g] = bmin(mn[g], xs[g]);
                mx[g] = bmax(mx[g], xs[g]);
                xn[g] = xs[g];
                dxn[g] = dxs[g];
                y[g] = z[g];
            }
            continue;
        }
        refused = rf;
        for (int l = 0; l < KB_LANES; l++) /* frun_refuse: the step as kst_store writes it */
            if ((refused >> l) & 1u) {
                const bst *zl = &z[l / KW];
                const int m = l % KW;
                double *tr = B->trial[l];
                for (int b = 0; b < 6; b++) {
                    tr[b] = zl->q[b][m];
                    tr[7 + b] = zl->v[b][m];
                }
                tr[6] = zl->s[m];
                tr[13] = zl->vs[m];
            }
#pragma GCC unroll 2
        for (int g = 0; g < ng; g++) {
            const unsigned a = (acc >> (g * KW)) & gm;
            tc[g] = bsel(a, ntc[g], tc[g]);
            tau[g] = bsel(a, t[g], tau[g]);
            mn[g] = bsel(a, bmin(mn[g], xs[g]), mn[g]);
            mx[g] = bsel(a, bmax(mx[g], xs[g]), mx[g]);
            xn[g] = bsel(a, xs[g], xn[g]);
            dxn[g] = bsel(a, dxs[g], dxn[g]);
#pragma GCC unroll 6
            for (int b = 0; b < 6; b++) {
                y[g].q[b] = bsel(a, z[g].q[b], y[g].q[b]);
                y[g].v[b] = bsel(a, z[g].v[b], y[g].v[b]);
            }
            y[g].s = bsel(a, z[g].s, y[g].s);
            y[g].vs = bsel(a, z[g].vs, y[g].vs);
        }
        for (int l = 0; l < ng * KW; l++)
            step[l] += (acc >> l) & 1u;
        break;
    }
#pragma GCC unroll 2
    for (int g = 0; g < BG; g++) {
        const int o = g * KW;
#pragma GCC unroll 6
        for (int b = 0; b < 6; b++) {
            bsto(B->q[b] + o, y[g].q[b]);
            bsto(B->v[b] + o, y[g].v[b]);
        }
        bsto(B->s + o, y[g].s), bsto(B->vs + o, y[g].vs);
        bsto(B->xn + o, xn[g]), bsto(B->dxn + o, dxn[g]);
        bsto(B->tau + o, tau[g]), bsto(B->tc + o, tc[g]);
        bsto(B->mn + o, mn[g]), bsto(B->mx + o, mx[g]);
    }
    B->refused = refused;
    unsigned stop = refused;
    for (int l = 0; l < KB_LANES; l++) {
        uint64_t m = l < ng * KW ? i + step[l] : 0; /* a group not computed took none */
        B->ran[l] = m;
        B->lim_steps[l] = B->lim_steps[l] > m ? B->lim_steps[l] - m : 0;
        B->ep[l] = ep[l] + 2 * m;
        if (((act >> l) & 1u) && B->lim_steps[l] == 0)
            stop |= 1u << l;
    }
    return stop;
}

#undef BG
