/* snap.c - snapshot files for save/restore. */
#include "snap.h"

#include "wormgear/wg_status.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define SNAP_MAGIC "# wormgeard snapshot, format 1"

int snap_name_ok(const char *name, char *why, size_t whylen)
{
    size_t n = strlen(name);
    int ok = n >= 1 && n <= 64 && name[0] != '.' && !strstr(name, "..");
    for (size_t i = 0; ok && i < n; i++) {
        char c = name[i];
        ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
             c == '_' || c == '-' || c == '.';
    }
    if (!ok)
        snprintf(why, whylen, "snapshot name '%.80s' refused: use 1-64 of [A-Za-z0-9_.-], "
                              "not starting with '.', no '/' or '..'", name);
    return ok ? WG_OK : WG_EINVAL;
}

void snap_take(snap *s, const wg_sim *sim, const char *scene)
{
    memset(s, 0, sizeof *s);
    snprintf(s->scene, sizeof s->scene, "%s", scene);
    wg_sim_snapshot(sim, &s->w);
}

static void put_period(FILE *f, const char *key, const wg_period *w)
{
    fprintf(f, "%s = %" PRIu64 " %a %a %d %d\n", key, w->period, w->min_xn, w->max_xn, w->motion,
            w->impacts);
}

static void put_all(FILE *f, const snap *s)
{
    fprintf(f, "%s\nscene = %s\nmodel = %d\nstepper = %d\nsteps_per_period = %d\n", SNAP_MAGIC,
            s->scene, s->w.model, s->w.stepper, s->w.steps_per_period);
    for (int i = 0; i < WG_NPARAM; i++)
        fprintf(f, "param %s = %a\n", wg_param_info_get(i)->name, s->w.p.v[i]);
    for (int i = 0; i < WG_NSTATE_MAX; i++)
        fprintf(f, "y %d = %a\n", i, s->w.y[i]);
    fprintf(f, "k = %" PRIu32 "\ntau = %a\ntau_c = %a\nperiod = %" PRIu64 "\nsteps = %" PRIu64 "\n",
            s->w.k, s->w.tau, s->w.tau_c, s->w.period, s->w.steps);
    const wg_ramp *r = &s->w.ramp;
    fprintf(f, "ramp = %d %s %a %a %a %a\n", r->active,
            r->active ? wg_param_info_get(r->id)->name : "-", r->v0, r->v1, r->tau0, r->dur);
    put_period(f, "cur", &s->w.cur);
    put_period(f, "last", &s->w.last);
}

static int file_path(char *path, size_t len, const char *dir, const char *name, char *why,
                     size_t whylen)
{
    int rc = snap_name_ok(name, why, whylen);
    if (rc)
        return rc;
    if ((size_t)snprintf(path, len, "%s/%s.wgstate", dir, name) >= len) {
        snprintf(why, whylen, "state directory path too long");
        return WG_EINVAL;
    }
    return WG_OK;
}

int snap_write(const snap *s, const char *dir, const char *name, char *path, size_t pathlen,
               char *why, size_t whylen)
{
    char tmp[600];
    int rc = file_path(path, pathlen, dir, name, why, whylen);
    if (rc)
        return rc;
    if (mkdir(dir, 0750) != 0 && errno != EEXIST) {
        snprintf(why, whylen, "cannot create state directory %s: %s", dir, strerror(errno));
        return WG_EIO;
    }
    snprintf(tmp, sizeof tmp, "%s.tmp.%d", path, (int)getpid());
    FILE *f = fopen(tmp, "w");
    if (!f) {
        snprintf(why, whylen, "cannot write %s: %s", tmp, strerror(errno));
        return WG_EIO;
    }
    put_all(f, s);
    int bad = ferror(f) | (fflush(f) != 0) | (fsync(fileno(f)) != 0);
    bad |= fclose(f) != 0;
    if (bad || rename(tmp, path) != 0) {
        snprintf(why, whylen, "cannot write %s: %s", path, strerror(errno));
        unlink(tmp);
        return WG_EIO;
    }
    return WG_OK;
}

/* ---- reading ------------------------------------------------------------- */

typedef struct rd {
    snap *s;
    const char *path;
    int line;
    char *why;
    size_t whylen;
    unsigned char seen_p[WG_NPARAM], seen_y[WG_NSTATE_MAX];
    int seen_head;
} rd;

static int bad(rd *r, int rc, const char *what, const char *val)
{
    snprintf(r->why, r->whylen, "%s:%d: %s '%.60s'", r->path, r->line, what, val);
    return rc;
}

static int num(rd *r, const char *v, double *out)
{
    char *end;
    *out = strtod(v, &end);
    return end == v || *end || !isfinite(*out) ? bad(r, WG_EINVAL, "not a finite number:", v)
                                               : WG_OK;
}

static int u64(rd *r, const char *v, uint64_t *out)
{
    char *end;
    errno = 0;
    *out = strtoull(v, &end, 10);
    return end == v || *end || errno || *v == '-' ? bad(r, WG_EINVAL, "not a count:", v) : WG_OK;
}

static int period_rec(rd *r, const char *v, wg_period *w)
{
    char a[64], b[64];
    unsigned long long per;
    int n = 0;
    if (sscanf(v, "%llu %63s %63s %d %d%n", &per, a, b, &w->motion, &w->impacts, &n) != 5 ||
        v[n] || num(r, a, &w->min_xn) || num(r, b, &w->max_xn))
        return bad(r, WG_EINVAL, "bad period record:", v);
    w->period = per;
    return WG_OK;
}

static int ramp_rec(rd *r, const char *v)
{
    wg_ramp *m = &r->s->w.ramp;
    char name[64], x[4][64];
    int n = 0;
    if (sscanf(v, "%d %63s %63s %63s %63s %63s%n", &m->active, name, x[0], x[1], x[2], x[3], &n) !=
            6 || v[n] || num(r, x[0], &m->v0) || num(r, x[1], &m->v1) || num(r, x[2], &m->tau0) ||
        num(r, x[3], &m->dur))
        return bad(r, WG_EINVAL, "bad ramp record:", v);
    m->id = m->active ? wg_param_lookup(name) : 0;
    if (m->active && (m->id < 0 || !(m->dur > 0)))
        return bad(r, WG_EINVAL, "bad ramp record:", v);
    return WG_OK;
}

static int indexed(rd *r, const char *key, const char *v)
{
    char msg[600];
    if (strncmp(key, "param ", 6) == 0) {
        int id = wg_param_lookup(key + 6);
        if (id < 0)
            return bad(r, WG_EUNKNOWN, "unknown parameter", key + 6);
        if (wg_param_parse(id, v, &r->s->w.p.v[id], msg, sizeof msg))
            return bad(r, WG_ERANGE, msg, "");
        r->seen_p[id] = 1;
        return WG_OK;
    }
    char *end;
    long i = strtol(key + 2, &end, 10);
    if (strncmp(key, "y ", 2) || *end || end == key + 2 || i < 0 || i >= WG_NSTATE_MAX)
        return bad(r, WG_EUNKNOWN, "unknown key", key);
    r->seen_y[i] = 1;
    return num(r, v, &r->s->w.y[i]);
}

static int field(rd *r, const char *key, const char *v)
{
    snap *s = r->s;
    uint64_t u = 0;
    double d;
    int rc;
    if (!strcmp(key, "scene"))
        return snprintf(s->scene, sizeof s->scene, "%s", v), WG_OK;
    if (!strcmp(key, "model") || !strcmp(key, "stepper") || !strcmp(key, "steps_per_period") ||
        !strcmp(key, "k") || !strcmp(key, "period") || !strcmp(key, "steps")) {
        if ((rc = u64(r, v, &u)) || u > (uint64_t)INT64_MAX)
            return rc ? rc : bad(r, WG_EINVAL, "too large:", v);
        if (!strcmp(key, "model")) s->w.model = (int)u;
        else if (!strcmp(key, "stepper")) s->w.stepper = (int)u;
        else if (!strcmp(key, "steps_per_period")) s->w.steps_per_period = u > 1000000 ? -1 : (int)u;
        else if (!strcmp(key, "k")) s->w.k = (uint32_t)u;
        else if (!strcmp(key, "period")) s->w.period = u;
        else s->w.steps = u;
        return WG_OK;
    }
    if (!strcmp(key, "tau") || !strcmp(key, "tau_c")) {
        if ((rc = num(r, v, &d)))
            return rc;
        *(key[3] ? &s->w.tau_c : &s->w.tau) = d;
        return WG_OK;
    }
    if (!strcmp(key, "ramp"))
        return ramp_rec(r, v);
    if (!strcmp(key, "cur") || !strcmp(key, "last"))
        return period_rec(r, v, key[0] == 'c' ? &s->w.cur : &s->w.last);
    return indexed(r, key, v);
}

static int parse_line(rd *r, char *line)
{
    line[strcspn(line, "\r\n")] = 0;
    if (r->line == 1) {
        r->seen_head = strcmp(line, SNAP_MAGIC) == 0;
        return r->seen_head ? WG_OK : bad(r, WG_EINVAL, "not a wormgeard snapshot:", line);
    }
    if (!line[0] || line[0] == '#')
        return WG_OK;
    char *eq = strstr(line, " = ");
    if (!eq)
        return bad(r, WG_EINVAL, "expected 'key = value', got", line);
    *eq = 0;
    return field(r, line, eq + 3);
}

static int complete(rd *r)
{
    for (int i = 0; i < WG_NPARAM; i++)
        if (!r->seen_p[i])
            return bad(r, WG_EINVAL, "missing parameter", wg_param_info_get(i)->name);
    for (int i = 0; i < WG_NSTATE_MAX; i++)
        if (!r->seen_y[i])
            return bad(r, WG_EINVAL, "missing state value", "y");
    if (!r->seen_head)
        return bad(r, WG_EINVAL, "empty file", "");
    return WG_OK;
}

int snap_read(snap *s, const char *dir, const char *name, char *why, size_t whylen)
{
    char path[600], buf[512];
    int rc = file_path(path, sizeof path, dir, name, why, whylen);
    if (rc)
        return rc;
    FILE *f = fopen(path, "r");
    if (!f) {
        snprintf(why, whylen, "cannot read %s: %s", path, strerror(errno));
        return WG_EIO;
    }
    memset(s, 0, sizeof *s);
    rd r = {.s = s, .path = path, .why = why, .whylen = whylen};
    while (!rc && fgets(buf, sizeof buf, f)) {
        r.line++;
        rc = parse_line(&r, buf);
    }
    fclose(f);
    return rc ? rc : complete(&r);
}

int snap_apply(const snap *s, wg_sim *sim, char *why, size_t whylen)
{
    return wg_sim_restore(sim, &s->w, why, whylen);
}
