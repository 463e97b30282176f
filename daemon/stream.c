/* stream.c - batched STATE / POINCARE / CONTACT publishing from the sink. */
#include "stream.h"

#include "wgd.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Poincare points this close (max norm) repeat: an orbit of period n. */
#define REGIME_TOL 1e-6

void stream_init(stream *s, int nstate, const wg_scale *scale, int state_on)
{
    memset(s, 0, sizeof *s);
    s->nstate = nstate;
    s->scale = *scale;
    s->st_on = state_on;
    s->decimation = 1;
    s->countdown = 0;
    s->ct_mesh = 1, s->ct_every = 1;
    for (int i = 0; i < PC_MAX; i++) {
        s->pc_rows[i] = s->pc_y[i];
        s->pc_bimp_rows[i] = s->pc_bimp[i];
        s->pc_bvmax_rows[i] = s->pc_bvmax[i];
    }
    stream_regime_reset(s);
}

void stream_stats_reset(stream *s)
{
    s->sections = s->impacts = 0;
    memset(s->bimp, 0, sizeof s->bimp);
    memset(s->bvmax, 0, sizeof s->bvmax);
}

void stream_regime_reset(stream *s)
{
    wg_tracker_init(&s->trk, s->nstate, REGIME_TOL);
    stream_stats_reset(s); /* impacts per period: of the new orbit only */
}

const char *stream_regime(const stream *s, char *buf, unsigned len)
{
    if (s->trk.n < 16)
        return "unknown";
    int n = wg_tracker_period(&s->trk, NULL);
    if (!n)
        return "aperiodic";
    snprintf(buf, len, "period-%d", n);
    return buf;
}

void stream_fini(stream *s) { (void)s; }

void stream_set_decimation(stream *s, int decimation)
{
    s->decimation = decimation < 1 ? 1 : decimation;
    if (s->countdown >= (uint64_t)s->decimation)
        s->countdown = (uint64_t)s->decimation - 1;
}

static void flush_state(wgd *d)
{
    stream *s = &d->st;
    double(*c)[ST_MAX] = s->st;
    wormgear_state_t m = {.step0 = s->st_step0, .decimation = s->decimation, .n = s->st_n,
                          .tau = c[0], .t_s = c[1], .omega = c[2], .xn = c[3], .dxn = c[4],
                          .force = c[5], .fb_x1 = c[6], .fb_y1 = c[7], .fb_z1 = c[8],
                          .fb_x2 = c[9], .fb_y2 = c[10], .fb_z2 = c[11], .theta1 = c[12],
                          .theta2 = c[13]};
    lcmio_pub_state(&d->io, &m);
    s->st_n = 0;
}

static void flush_poincare(wgd *d)
{
    stream *s = &d->st;
    double(*c)[PC_MAX] = s->pc;
    wormgear_poincare_t m = {.nstate = s->nstate, .n = s->pc_n, .period = s->pc_period,
                             .tau = c[0], .t_s = c[1], .omega = c[2], .xn = c[3], .dxn = c[4],
                             .force = c[5], .min_xn = c[6], .max_xn = c[7],
                             .motion = s->pc_motion, .impacts = s->pc_impacts, .y = s->pc_rows,
                             .nbearing = WG_NBEARING, .bearing_impacts = s->pc_bimp_rows,
                             .bearing_vmax = s->pc_bvmax_rows};
    lcmio_pub_poincare(&d->io, &m);
    s->pc_n = 0;
}

static void flush_contact(wgd *d)
{
    stream *s = &d->st;
    wormgear_contact_t m = {.bearing_every = s->ct_every, .n = s->ct_n, .tau = s->ct_tau, .t_s = s->ct_ts,
                            .velocity = s->ct_vel, .period = s->ct_period,
                            .contact = s->ct_contact, .kind = s->ct_kind};
    lcmio_pub_contact(&d->io, &m);
    s->ct_n = 0;
}

void stream_flush(wgd *d)
{
    if (d->st.st_n)
        flush_state(d);
    if (d->st.pc_n)
        flush_poincare(d);
    if (d->st.ct_n)
        flush_contact(d);
}

void stream_scope(wgd *d)
{
    wg_outputs o;
    wg_sim_outputs(&d->sim, &o);
    wormgear_scope_t m = {.t_s = wg_scale_seconds(&d->scene.scale, d->sim.tau),
                          .tau = d->sim.tau, .omega = d->sim.p.v[WG_P_OMEGA], .xn = o.xn,
                          .dxn = o.dxn, .force = o.F};
    lcmio_pub_scope(&d->io, &m);
}

static void on_step(void *ctx, const wg_sim *sim)
{
    wgd *d = ctx;
    stream *s = &d->st;
    if (s->countdown--)
        return;
    s->countdown = (uint64_t)s->decimation - 1;
    if (s->st_n == 0)
        s->st_step0 = (int64_t)sim->steps;
    wg_outputs o;
    wg_sim_outputs(sim, &o);
    int i = s->st_n++;
    double(*c)[ST_MAX] = s->st;
    c[0][i] = sim->tau;
    c[1][i] = wg_scale_seconds(&s->scale, sim->tau);
    c[2][i] = sim->p.v[WG_P_OMEGA];
    c[3][i] = o.xn;
    c[4][i] = o.dxn;
    c[5][i] = o.F;
    for (int j = 0; j < 6; j++)
        c[6 + j][i] = o.fb[j];
    double th[2];
    wg_sim_angles(sim, th);
    c[12][i] = th[0];
    c[13][i] = th[1];
    if (s->st_n == ST_MAX)
        flush_state(d);
}

static void on_section(void *ctx, const wg_section *sec)
{
    wgd *d = ctx;
    stream *s = &d->st;
    int i = s->pc_n++;
    double(*c)[PC_MAX] = s->pc;
    s->pc_period[i] = (int64_t)sec->stats.period;
    c[0][i] = sec->tau;
    c[1][i] = wg_scale_seconds(&s->scale, sec->tau);
    c[2][i] = sec->omega;
    c[3][i] = sec->out.xn;
    c[4][i] = sec->out.dxn;
    c[5][i] = sec->out.F;
    c[6][i] = sec->stats.min_xn;
    c[7][i] = sec->stats.max_xn;
    s->pc_motion[i] = (int8_t)sec->stats.motion;
    s->pc_impacts[i] = sec->stats.impacts;
    memcpy(s->pc_y[i], sec->y, sizeof s->pc_y[i]);
    s->sections++;
    s->impacts += (uint64_t)sec->stats.impacts;
    for (int j = 0; j < WG_NBEARING; j++) { /* the period just completed */
        s->pc_bimp[i][j] = sec->stats.bimpacts[j];
        s->pc_bvmax[i][j] = sec->stats.bvmax[j];
        s->bimp[j] += (uint64_t)sec->stats.bimpacts[j];
        s->bvmax[j] = fmax(s->bvmax[j], sec->stats.bvmax[j]);
    }
    s->motion = sec->stats.motion;
    s->last = sec->stats;
    wg_tracker_push(&s->trk, sec);
    if (s->pc_n == PC_MAX)
        flush_poincare(d);
}

void stream_set_contacts(stream *s, int contacts, int bearing_every)
{
    s->ct_mesh = contacts != CONTACTS_NONE;
    s->ct_every = contacts == CONTACTS_ALL ? bearing_every : 0;
}

/* Published under the contacts setting? Bearings count per bearing, so
 * each one is thinned evenly. */
static int contact_kept(stream *s, int contact)
{
    uint64_t k = s->ct_seen[contact]++;
    int keep = contact == 0 ? s->ct_mesh : s->ct_every > 0 && k % (uint64_t)s->ct_every == 0;
    s->ct_thinned += !keep;
    return keep;
}

static void on_event(void *ctx, const wg_event *ev)
{
    wgd *d = ctx;
    stream *s = &d->st;
    if (ev->contact < 0 || ev->contact >= WG_NCONTACT)
        return;
    if (!contact_kept(s, ev->contact))
        return;
    int i = s->ct_n++;
    s->ct_tau[i] = ev->tau;
    s->ct_ts[i] = wg_scale_seconds(&s->scale, ev->tau);
    s->ct_vel[i] = ev->velocity;
    s->ct_period[i] = (int64_t)ev->period;
    s->ct_contact[i] = (int8_t)ev->contact;
    s->ct_kind[i] = (int8_t)ev->kind;
    if (s->ct_n == CT_MAX)
        flush_contact(d);
}

wg_sink stream_sink(wgd *d)
{
    return (wg_sink){d, d->st.st_on ? on_step : NULL, on_section, on_event};
}
