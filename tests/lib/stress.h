/* stress.h - helpers shared by the stress tests (one header, static only). */
#ifndef WG_STRESS_H
#define WG_STRESS_H

#include "test.h"
#include "test_sim.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_sim.h"
#include "wormgear/wg_status.h"

#include <stdint.h>

/* Parameters of a shipped scene (WG_SCENE_PATH is set by ctest). */
static inline wg_params stress_scene(const char *name)
{
    wg_scene sc;
    char why[600];
    int rc = wg_scene_open(&sc, name, why, sizeof why);
    if (rc) {
        fprintf(stderr, "scene %s: %s\n", name, why);
        exit(2);
    }
    return sc.p;
}

/* 1 if all n values are finite. */
static inline int stress_finite(const double *y, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(y[i]))
            return 0;
    return 1;
}

static inline double stress_maxabs(const double *y, int n)
{
    double m = 0;
    for (int i = 0; i < n; i++)
        m = fmax(m, fabs(y[i]));
    return m;
}

/* FNV-1a over raw bytes: bit-identical streams hash equal. */
static inline uint64_t stress_fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *c = p;
    for (size_t i = 0; i < n; i++) {
        h ^= c[i];
        h *= 1099511628211ull;
    }
    return h;
}
#define STRESS_FNV0 14695981039346656037ull

#endif
