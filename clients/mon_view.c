/* mon_view.c - wgmon's trace and Poincare scatter as text (see mon_view.h). */
#include "mon_view.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TWO_PI 6.283185307179586

enum {
    LAB = 8,         /* columns of the y labels left of a canvas */
    STROBE_SPP = 8,  /* fewer samples per period than this: fold them */
    MAXW = 1000      /* widest canvas */
};

/* ---- rings ------------------------------------------------------------------- */

int mon_trace_alloc(mon_trace *tr, long cap)
{
    memset(tr, 0, sizeof *tr);
    tr->cap = cap;
    tr->step = malloc(sizeof *tr->step * (size_t)cap);
    tr->x = malloc(sizeof *tr->x * (size_t)cap);
    tr->t = malloc(sizeof *tr->t * (size_t)cap);
    return tr->step && tr->x && tr->t ? 0 : -1;
}

int mon_sections_alloc(mon_sections *s, long cap)
{
    memset(s, 0, sizeof *s);
    s->cap = cap;
    s->t = malloc(sizeof *s->t * (size_t)cap);
    s->x = malloc(sizeof *s->x * (size_t)cap);
    s->v = malloc(sizeof *s->v * (size_t)cap);
    s->imp = malloc(sizeof *s->imp * (size_t)cap);
    s->mot = malloc(sizeof *s->mot * (size_t)cap);
    return s->t && s->x && s->v && s->imp && s->mot ? 0 : -1;
}

void mon_trace_free(mon_trace *tr) { free(tr->step), free(tr->x), free(tr->t); }

void mon_sections_free(mon_sections *s)
{
    free(s->t), free(s->x), free(s->v), free(s->imp), free(s->mot);
}

void mon_trace_push(mon_trace *tr, int64_t step, double x, double t)
{
    long j = tr->n++ % tr->cap;
    tr->step[j] = step, tr->x[j] = x, tr->t[j] = t;
}

void mon_sections_push(mon_sections *s, double t, double x, double v, int imp, int mot)
{
    long j = s->n++ % s->cap;
    s->t[j] = t, s->x[j] = x, s->v[j] = v, s->imp[j] = imp, s->mot[j] = mot;
}

long mon_view_from(const double *t, long n, long cap, double since)
{
    long lo = n > cap ? n - cap : 0, hi = n;
    while (lo < hi) {
        long mid = lo + (hi - lo) / 2;
        if (t[mid % cap] < since)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

const char *mon_view_span(const mon_view_ctx *c, char *buf, size_t len)
{
    double s = c->now - c->since;
    if (s >= c->window_s)
        snprintf(buf, len, "%g", c->window_s);
    else if (s < 10)
        snprintf(buf, len, "%.2g", s > 0 ? s : 0.0);
    else
        snprintf(buf, len, "%.0f", s);
    return buf;
}

int mon_view_strobe(const mon_trace *tr, const mon_view_ctx *c)
{
    return c->N > 0 && tr->decimation > 0 && (double)c->N / tr->decimation < STROBE_SPP;
}

/* ---- a panel: titles, a canvas with y labels, an axis row, label rows ---------- */

typedef struct panel {
    int w, h, ntitle, nxlab;
    char title[2][320];
    char ytop[16], ybot[16];
    char *cv;                 /* w x h cells */
    char axis[MAXW + 1];
    char xlab[2][MAXW + 1];
    char xunit[2][LAB + 1];   /* the unit of each label row, left of it */
} panel;

static void cell(panel *p, int x, int y, char ch)
{
    if (x >= 0 && x < p->w && y >= 0 && y < p->h)
        p->cv[y * p->w + x] = ch;
}

static void blank(char *row, int w)
{
    memset(row, ' ', (size_t)w);
    row[w] = 0;
}

/* Label s centred on column x of row (w wide), if it clears the text that
 * ends at `after`: the column after it, or after unchanged. */
static int place(char *row, int w, int x, const char *s, int after)
{
    int n = (int)strlen(s), x0 = x - n / 2;
    x0 = x0 < 0 ? 0 : x0 + n > w ? w - n : x0;
    if (x0 < after || x0 < 0)
        return after;
    memcpy(row + x0, s, (size_t)n);
    return x0 + n + 1;
}

/* Row r of a panel, LAB + w columns, into out. */
static void panel_row(const panel *p, int r, char *out)
{
    int width = LAB + p->w;
    blank(out, width);
    if (r < p->ntitle) {
        size_t n = strlen(p->title[r]);
        memcpy(out, p->title[r], n < (size_t)width ? n : (size_t)width);
    } else if ((r -= p->ntitle) < p->h) {
        if (r == 0 || r == p->h - 1)
            memcpy(out, r ? p->ybot : p->ytop, strlen(r ? p->ybot : p->ytop));
        memcpy(out + LAB, p->cv + r * p->w, (size_t)p->w);
    } else if ((r -= p->h) == 0) {
        memcpy(out + LAB, p->axis, (size_t)p->w);
    } else if (r - 1 < p->nxlab) {
        memcpy(out, p->xunit[r - 1], strlen(p->xunit[r - 1]));
        memcpy(out + LAB, p->xlab[r - 1], (size_t)p->w);
    }
}

/* A title in the first of its forms that fits w columns: call with the
 * longest form (first 1), then shorter ones (first 0); a shorter form
 * replaces the title only when what is there is too wide, so the last is
 * taken whatever its width. */
__attribute__((format(printf, 4, 5)))
static void fit(char (*dst)[320], int w, int first, const char *fmt, ...)
{
    if (!first && (int)strlen(*dst) <= w)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(*dst, sizeof *dst, fmt, ap);
    va_end(ap);
}

static int panel_rows(const panel *p) { return p->ntitle + p->h + 1 + p->nxlab; }

/* ---- the trace ------------------------------------------------------------------ */

/* The samples to draw: [*i0, tr->n). Scrolling: the run of rising steps
 * back to the window's start *b0 (the end of the newest sample's period
 * less `periods` periods); stroboscopic: the last window_s seconds. */
static void trace_span(const mon_trace *tr, const mon_view_ctx *c, int strobe, long *i0,
                       int64_t *b0)
{
    long first = tr->n > tr->cap ? tr->n - tr->cap : 0, cap = tr->cap;
    int64_t pn = (int64_t)c->periods * c->N;
    *b0 = 0;
    if (strobe || tr->n == 0 || c->N <= 0) {
        *i0 = mon_view_from(tr->t, tr->n, tr->cap, c->now - c->window_s);
        return;
    }
    int64_t s = tr->step[(tr->n - 1) % cap];
    *b0 = (s / c->N + 1) * c->N - pn;
    long i = tr->n - 1;
    while (i > first && tr->step[(i - 1) % cap] >= *b0 &&
           tr->step[(i - 1) % cap] < tr->step[i % cap])
        i--;
    *i0 = i;
}

/* Column of a sample: its place in the window (scrolling) or its phase in
 * the window's periods from psi = 0 (stroboscopic). */
static int trace_col(const panel *p, int64_t step, int64_t b0, int64_t pn, int strobe)
{
    int64_t u = strobe ? ((step % pn) + pn) % pn : step - b0;
    int x = (int)((double)u / (double)pn * p->w);
    return x < 0 ? 0 : x >= p->w ? p->w - 1 : x;
}

static void trace_plot(panel *p, const mon_trace *tr, long i0, int64_t b0, int64_t pn,
                       int strobe, double lo, double hi)
{
    int px = -1, py = -1;
    for (long i = i0; i < tr->n; i++) {
        long j = i % tr->cap;
        int x = trace_col(p, tr->step[j], b0, pn, strobe);
        int y = (int)lround((hi - tr->x[j]) / (hi - lo) * (p->h - 1));
        if (!strobe && px >= 0 && x >= px && abs(y - py) > 1) /* join the samples */
            for (int k = (y < py ? y : py) + 1; k < (y < py ? py : y); k++)
                cell(p, x, k, '|');
        cell(p, x, y, '*');
        px = x, py = y;
    }
}

/* Axis ticks at period boundaries (every k periods, k so labels fit) and
 * their labels: periods (0 .. P folded, -P .. 0 scrolling) and ms. */
static void trace_axis(panel *p, const mon_view_ctx *c, int strobe, double t_ms)
{
    int P = c->periods, k = 1000, a0 = 0, a1 = 0;
    static const int steps[] = {1, 2, 5, 10, 20, 50, 100, 200, 500};
    for (int i = 8; i >= 0; i--)
        k = steps[i] * p->w >= 7 * P ? steps[i] : k; /* labels 7 columns apart at least */
    for (int i = 0; i < 2; i++)
        blank(p->xlab[i], p->w);
    snprintf(p->xunit[0], sizeof p->xunit[0], "%7s", "periods");
    snprintf(p->xunit[1], sizeof p->xunit[1], "%7s", "ms");
    memset(p->axis, '-', (size_t)p->w);
    p->axis[p->w] = 0;
    for (int j = 0; j <= P; j += k) {
        int x = j * p->w / P;
        x = x >= p->w ? p->w - 1 : x;
        p->axis[x] = '+';
        char s[32];
        int lab = strobe ? j : j - P;
        snprintf(s, sizeof s, "%d", lab);
        int b0 = a0;
        a0 = place(p->xlab[0], p->w, x, s, a0);
        if (t_ms > 0 && a0 != b0) {
            snprintf(s, sizeof s, "%.3g", lab * t_ms);
            a1 = place(p->xlab[1], p->w, x, s, a1);
        }
    }
}

static void trace_panel(panel *p, const mon_trace *tr, const mon_view_ctx *c, int compact)
{
    int strobe = mon_view_strobe(tr, c);
    int64_t pn = (int64_t)c->periods * (c->N > 0 ? c->N : 1), b0;
    long i0;
    trace_span(tr, c, strobe, &i0, &b0);
    double lo = INFINITY, hi = -INFINITY;
    for (long i = i0; i < tr->n; i++)
        lo = fmin(lo, tr->x[i % tr->cap]), hi = fmax(hi, tr->x[i % tr->cap]);
    double t_ms = c->omega > 0 && c->omega_n_rad_s > 0 ? TWO_PI / (c->omega * c->omega_n_rad_s) * 1e3 : 0;
    int tw = LAB + p->w;
    char T[32] = "", Ts[32] = "";
    if (t_ms > 0)
        snprintf(T, sizeof T, " (T = %.3g ms)", t_ms), snprintf(Ts, sizeof Ts, ", T %.3g ms", t_ms);
    fit(&p->title[0], tw, 1, "x_n%s over %d mesh periods%s", strobe ? ", STROBOSCOPIC," : "",
        c->periods, T);
    fit(&p->title[0], tw, 0, "x_n%s %d periods%s", strobe ? " STROBOSCOPIC," : ",", c->periods, Ts);
    fit(&p->title[0], tw, 0, "x_n%s %d periods", strobe ? " STROBOSCOPIC," : ",", c->periods);
    double spp = tr->decimation > 0 && c->N > 0 ? (double)c->N / tr->decimation : 0.0;
    if (i0 >= tr->n) {
        fit(&p->title[1], tw, 1, "no STATE samples %s", strobe ? "in the window" : "yet");
        lo = 0, hi = 1;
    } else if (strobe) {
        char span[16];
        mon_view_span(c, span, sizeof span);
        fit(&p->title[1], tw, 1, "%.2g samples/period: the last %s s folded on the window by phase "
            "from psi = 0", spp, span);
        fit(&p->title[1], tw, 0, "%.2g samples/period: last %s s folded by phase", spp, span);
        fit(&p->title[1], tw, 0, "%.2g/period, %s s folded", spp, span);
    } else {
        fit(&p->title[1], tw, 1, "scrolling, %.0f samples/period, newest at the right", spp);
        fit(&p->title[1], tw, 0, "scrolling, %.0f samples/period", spp);
    }
    if (hi - lo < 1e-9)
        lo -= 0.5, hi += 0.5;
    p->ntitle = compact ? 1 : 2;
    p->nxlab = !compact && t_ms > 0 ? 2 : 1;
    snprintf(p->ytop, sizeof p->ytop, "%7.4g", hi);
    snprintf(p->ybot, sizeof p->ybot, "%7.4g", lo);
    trace_plot(p, tr, i0, b0, pn, strobe, lo, hi);
    trace_axis(p, c, strobe, t_ms);
}

/* ---- the scatter ---------------------------------------------------------------- */

static void scatter_panel(panel *p, const mon_sections *s, const mon_view_ctx *c, int compact)
{
    static const char shade[] = ".:oO#@";
    long i0 = mon_view_from(s->t, s->n, s->cap, c->now - c->window_s);
    double x0 = INFINITY, x1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    for (long i = i0; i < s->n; i++) {
        long j = i % s->cap;
        x0 = fmin(x0, s->x[j]), x1 = fmax(x1, s->x[j]), v0 = fmin(v0, s->v[j]), v1 = fmax(v1, s->v[j]);
    }
    if (i0 >= s->n)
        x0 = v0 = 0, x1 = v1 = 1;
    double px = fmax(1e-6, 0.05 * (x1 - x0)), pv = fmax(1e-6, 0.05 * (v1 - v0));
    x0 -= px, x1 += px, v0 -= pv, v1 += pv;
    int cells = 0;
    for (long i = i0; i < s->n; i++) {
        long j = i % s->cap;
        int x = (int)((s->x[j] - x0) / (x1 - x0) * p->w), y = (int)((v1 - s->v[j]) / (v1 - v0) * p->h);
        if (x < 0 || x >= p->w || y < 0 || y >= p->h)
            continue;
        char *ch = &p->cv[y * p->w + x];
        const char *q = strchr(shade, *ch);
        cells += *ch == ' ';
        *ch = *ch == ' ' ? shade[0] : q && q[1] ? q[1] : *ch;
    }
    int tw = LAB + p->w;
    fit(&p->title[0], tw, 1, "Poincare section psi = 0: x_n' (up) vs x_n");
    fit(&p->title[0], tw, 0, "Poincare psi=0: x_n' vs x_n");
    char span[16];
    mon_view_span(c, span, sizeof span);
    fit(&p->title[1], tw, 1, "last %s s: %ld sections in %d cells", span, s->n - i0, cells);
    fit(&p->title[1], tw, 0, "%ld sections, %d cells", s->n - i0, cells);
    p->ntitle = compact ? 1 : 2;
    snprintf(p->ytop, sizeof p->ytop, "%7.4g", v1);
    snprintf(p->ybot, sizeof p->ybot, "%7.4g", v0);
    memset(p->axis, '-', (size_t)p->w);
    p->axis[0] = p->axis[p->w - 1] = '+';
    p->axis[p->w] = 0;
    p->nxlab = !compact && c->length_m > 0 ? 2 : 1;
    for (int r = 0; r < p->nxlab; r++) {
        double k = r ? c->length_m * 1e6 : 1.0;
        char a[32], b[32];
        blank(p->xlab[r], p->w);
        snprintf(a, sizeof a, "%.4g", x0 * k);
        snprintf(b, sizeof b, "%.4g", x1 * k);
        int n = (int)strlen(b);
        memcpy(p->xlab[r], a, strlen(a) < (size_t)p->w ? strlen(a) : (size_t)p->w);
        if (n < p->w)
            memcpy(p->xlab[r] + p->w - n, b, (size_t)n);
        snprintf(p->xunit[r], sizeof p->xunit[r], "%7s", r ? "um" : "x_n");
    }
}

/* ---- layout ---------------------------------------------------------------------- */

static void emit(mon_text *f, const panel *a, const panel *b, int rows)
{
    char la[LAB + MAXW + 1], lb[LAB + MAXW + 1];
    for (int r = 0; r < rows; r++) {
        panel_row(a, r, la);
        if (b) {
            panel_row(b, r, lb);
            mon_text_put(f, 0, "%s   %s", la, lb);
        } else {
            mon_text_put(f, 0, "%s", la);
        }
        mon_text_nl(f);
    }
}

void mon_view_plots(mon_text *f, const mon_trace *tr, const mon_sections *pc,
                    const mon_view_ctx *c, int rows)
{
    /* side by side from 100 columns, or when stacking leaves < 5 canvas rows */
    int side = f->cols >= 100 || (rows - 12) / 2 < 5, blocks = side ? 1 : 2, compact = 0;
    int w = side ? (f->cols - 2 * LAB - 3) / 2 : f->cols - LAB - 1;
    w = w > MAXW ? MAXW : w;
    int h = (rows - blocks * 6) / blocks;   /* 2 titles, axis, 2 label rows + 1 spare */
    if (h < 3)
        compact = 1, h = (rows - blocks * 3) / blocks;
    if (h < 3 || w < 12 || c->periods < 1)
        return;
    panel a = {.w = w, .h = h}, b = {.w = w, .h = h};
    a.cv = malloc((size_t)(w * h)), b.cv = malloc((size_t)(w * h));
    if (a.cv && b.cv) {
        memset(a.cv, ' ', (size_t)(w * h)), memset(b.cv, ' ', (size_t)(w * h));
        trace_panel(&a, tr, c, compact);
        scatter_panel(&b, pc, c, compact);
        int wrap = f->wrap;
        f->wrap = 0;
        if (side) {
            int ra = panel_rows(&a), rb = panel_rows(&b);
            emit(f, &a, &b, ra > rb ? ra : rb);
        } else {
            emit(f, &a, NULL, panel_rows(&a));
            if (blocks == 2)
                emit(f, &b, NULL, panel_rows(&b));
        }
        f->wrap = wrap;
    }
    free(a.cv), free(b.cv);
}
