/* stream.h - the batched output streams STATE, POINCARE and CONTACT.
 *
 * The simulation's sink callbacks append to fixed-size batches held here
 * (no allocation in the step path); a batch is published when it is full
 * or when stream_flush runs (every 20 ms from the loop: ~50 messages/s per
 * channel). STATE is decimated to a sample every `decimation` steps;
 * POINCARE and CONTACT are never decimated. The section callback also keeps
 * the motion class and impact counts STATUS reports. */
#ifndef WGD_STREAM_H
#define WGD_STREAM_H

#include <stdint.h>

#include "wormgear/wg_regime.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_sim.h"

enum { ST_MAX = 400, PC_MAX = 200, CT_MAX = 1024, ST_NCOL = 14 };

struct wgd;

typedef struct stream {
    wg_scale scale;                 /* tau -> seconds (wg_scale_seconds) */
    /* STATE */
    int st_on;                      /* 0: no STATE at all (state_rate_hz = 0) */
    int st_n, decimation;
    uint64_t countdown;             /* steps until the next sample */
    int64_t st_step0;
    double st[ST_NCOL][ST_MAX];     /* tau t_s omega xn dxn F fb[6] theta1 theta2 */
    /* POINCARE */
    int pc_n, nstate;
    int64_t pc_period[PC_MAX];
    double pc[9][PC_MAX];           /* tau t_s omega xn dxn F min max (unused) */
    int8_t pc_motion[PC_MAX];
    int32_t pc_impacts[PC_MAX];
    double pc_y[PC_MAX][WG_NSTATE_MAX];
    double *pc_rows[PC_MAX];
    int32_t pc_bimp[PC_MAX][WG_NBEARING]; /* bearing impacts and largest speeds */
    double pc_bvmax[PC_MAX][WG_NBEARING];
    int32_t *pc_bimp_rows[PC_MAX];
    double *pc_bvmax_rows[PC_MAX];
    /* CONTACT */
    int ct_mesh, ct_every;          /* published: mesh events; every Nth of a bearing's (0: none) */
    uint64_t ct_seen[WG_NCONTACT];  /* events per contact, published or not */
    uint64_t ct_thinned;            /* events not published (contacts setting), since start */
    int ct_n;
    double ct_tau[CT_MAX], ct_ts[CT_MAX], ct_vel[CT_MAX];
    int64_t ct_period[CT_MAX];
    int8_t ct_contact[CT_MAX], ct_kind[CT_MAX];
    /* statistics for STATUS (reset by the reader) */
    uint64_t sections, impacts;
    uint64_t bimp[WG_NBEARING];     /* bearing impacts in the completed periods */
    double bvmax[WG_NBEARING];      /* their largest |velocity| */
    int motion;                     /* of the last completed period */
    wg_period last;
    wg_tracker trk;                 /* last Poincare points, for the regime on STATUS */
} stream;

/* Empty batches for a sim with nstate values; the scene's scale converts
 * tau to seconds. */
void stream_init(stream *s, int nstate, const wg_scale *scale, int state_on);

/* Nothing to free; present for the init/fini pairing. */
void stream_fini(stream *s);

/* The sink to pass to wg_sim_run (ctx = the daemon). */
wg_sink stream_sink(struct wgd *d);

/* Publish one SCOPE sample of the current state (scalars, for lcm-spy). */
void stream_scope(struct wgd *d);

/* Publish every non-empty batch now. */
void stream_flush(struct wgd *d);

/* Zero the interval's counts STATUS reads: sections, mesh impacts, the
 * bearings' impacts and largest speeds (report.c, at each STATUS). */
void stream_stats_reset(stream *s);

/* Forget the tracked Poincare points and the impacts-per-period count
 * (after a parameter or state change: they describe the new orbit only). */
void stream_regime_reset(stream *s);

/* Regime of the tracked points: "period-N", "aperiodic" (no period <= 32
 * over the last 96 periods: quasi-periodic, chaotic or still settling),
 * "unknown" (fewer than 16 periods since the last change). */
const char *stream_regime(const stream *s, char *buf, unsigned len);

/* Which contact events to publish from now on (conf.h CONTACTS_*): all
 * (the mesh's, and every Nth of each bearing's, N = bearing_every >= 1),
 * mesh (only the mesh's) or none. Call stream_flush first: a CONTACT
 * message holds one setting. */
void stream_set_contacts(stream *s, int contacts, int bearing_every);

/* Set the STATE decimation (steps per sample, >= 1). */
void stream_set_decimation(stream *s, int decimation);

#endif
