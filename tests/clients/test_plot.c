/* test_plot.c - the bifurcation figure draws each of a point's Poincare
 * spots once (wgsweep's figures took 1.1 s of the Table-3 study's 3.6 s
 * drawing a period-1 orbit's 128 coincident sections 128 times): a point
 * whose sections repeat renders exactly as the same point with each
 * distinct section once, and two sections a third of a pixel apart are
 * both drawn, as is a spot at another point's height; and an x-y figure of
 * data with no spread (a period-1 orbit's Poincare map) ends and shows
 * its dot; axis ticks end and their labels tell them apart, and the y
 * axis title keeps clear of long tick labels; a ramp run's caption says what
 * the ramp did, not a transient and record it never ran (the SVG's <desc>); points
 * not measured break the min x_n line; a continuation figure's event label
 * drawn across a curve keeps a white halo between its letters and the
 * curve. The figures are read back as pixels with cairo. */
#include "test.h"

#include "plot.h"
#include "plot_cont.h"
#include "plot_draw.h"
#include "sweep_out.h"

#include <cairo.h>
#include <unistd.h>

enum { NPTS = 21 };

static char dir[64];

/* Up and down sweeps over omega 1.0 ... 1.4: period 1, then period 2
 * (sections alternating), then a point with 128 distinct sections. */
static void make_points(wg_point *up, wg_point *down, int repeat)
{
    for (int i = 0; i < NPTS; i++) {
        wg_point *p = &up[i];
        memset(p, 0, sizeof *p);
        p->value = 1.0 + 0.02 * i;
        p->regime = WG_REGIME_PERIODIC;
        p->period = i < 10 ? 1 : 2;
        p->min_xn = 0.5;
        double a = 1.1 + 0.01 * i, b = 1.3 - 0.005 * i;
        int ndist = p->period;
        if (i == NPTS - 1) { /* scattered: every section its own spot */
            p->regime = WG_REGIME_CHAOTIC;
            p->period = 0;
            ndist = WG_POINT_NSEC;
        }
        p->nsec = repeat ? WG_POINT_NSEC : ndist;
        for (int k = 0; k < p->nsec; k++)
            p->xn[k] = ndist == WG_POINT_NSEC ? 1.05 + 0.003 * k : k % ndist ? b : a;
        down[i] = *p;
        down[i].xn[0] += 0.002; /* the down sweep's spots a little apart */
        if (repeat)
            for (int k = 0; k < p->nsec; k += ndist)
                down[i].xn[k] = down[i].xn[0];
    }
}

static cairo_surface_t *draw(const char *name, const wg_point *up, const wg_point *down)
{
    char path[128], why[256];
    snprintf(path, sizeof path, "%s/%s.png", dir, name);
    plot_bif pb = {"test: bifurcation diagram", "ω  (-)", up, down, NPTS, NPTS, 1.0, NULL, 0,
                   {0, NULL, 0}, {0, NULL, 0}, {"png", {"caption", NULL, NULL, NULL}}};
    ASSERT_EQ_INT(plot_bifurcation(path, &pb, why, sizeof why), 0);
    cairo_surface_t *s = cairo_image_surface_create_from_png(path);
    ASSERT_EQ_INT(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
    unlink(path);
    return s;
}

/* Channel values that differ between two figures of one size. */
static long differ(cairo_surface_t *a, cairo_surface_t *b)
{
    int h = cairo_image_surface_get_height(a), st = cairo_image_surface_get_stride(a);
    ASSERT_EQ_INT(cairo_image_surface_get_width(a), cairo_image_surface_get_width(b));
    ASSERT_EQ_INT(h, cairo_image_surface_get_height(b));
    const unsigned char *pa = cairo_image_surface_get_data(a), *pb = cairo_image_surface_get_data(b);
    long n = 0;
    for (long i = 0; pa && pb && i < (long)h * st; i++)
        n += pa[i] != pb[i];
    return n;
}

static void setup(void)
{
    static int once;
    if (!once++)
        atexit(plot_fini); /* cairo's and fontconfig's caches, as wgsweep does */
    snprintf(dir, sizeof dir, "/tmp/test_plot.XXXXXX");
    ASSERT_TRUE(mkdtemp(dir) != NULL);
}

static void test_repeated_sections_drawn_once(void)
{
    static wg_point up[NPTS], down[NPTS], up1[NPTS], down1[NPTS];
    setup();
    make_points(up, down, 1);
    make_points(up1, down1, 0);
    cairo_surface_t *a = draw("repeat", up, down), *b = draw("once", up1, down1);
    ASSERT_EQ_INT(differ(a, b), 0);
    cairo_surface_destroy(a);
    cairo_surface_destroy(b);
    rmdir(dir);
}

/* Two spots 3e-4 apart, about a third of a pixel on this axis (x_n 1.0
 * ... 1.45 over ~500 px), at ten sub-pixel phases: each pair renders
 * otherwise than its first spot alone. */
static void test_near_sections_both_drawn(void)
{
    static wg_point up[NPTS], down[NPTS], one[NPTS];
    setup();
    make_points(up, down, 1);
    int collapsed = 0;
    for (int j = 0; j < 10; j++) {
        double h = 1.25 + 1.37e-4 * j; /* point 15 (period 2) at h and h + 3e-4 */
        for (int k = 0; k < WG_POINT_NSEC; k++)
            up[15].xn[k] = k % 2 ? h + 3e-4 : h;
        memcpy(one, up, sizeof one);
        for (int k = 0; k < WG_POINT_NSEC; k++)
            one[15].xn[k] = h;
        cairo_surface_t *a = draw("near", up, down), *b = draw("near-one", one, down);
        if (differ(a, b) == 0) {
            TEST_FAIL_("spots at x_n %.6f and %.6f drawn as one", h, h + 3e-4);
            collapsed++;
        }
        cairo_surface_destroy(a);
        cairo_surface_destroy(b);
    }
    ASSERT_EQ_INT(collapsed, 0);
    rmdir(dir);
}

/* Each point's spots are its own: a spot at the height of another
 * point's is drawn too. */
static void test_each_point_its_own_spots(void)
{
    static wg_point up[NPTS], down[NPTS], none[NPTS];
    setup();
    make_points(up, down, 1);
    for (int k = 0; k < WG_POINT_NSEC; k++)
        up[6].xn[k] = up[5].xn[0]; /* both period 1, at one height */
    memcpy(none, up, sizeof none);
    none[6].nsec = 0;
    cairo_surface_t *a = draw("shared", up, down), *b = draw("shared-none", none, down);
    if (differ(a, b) == 0)
        TEST_FAIL_("a point's spot at another point's height was not drawn");
    cairo_surface_destroy(a);
    cairo_surface_destroy(b);
    rmdir(dir);
}

/* A period-1 orbit's Poincare map: 2000 sections within 1e-15 of each
 * other (and once all equal to the bit). Its axes' ticks were a running
 * sum whose step was under the values' ulp, so the figure never ended;
 * now it is drawn in the unit window that equal data always had, the dot
 * in its middle. */
static void test_poincare_of_period_one(void)
{
    enum { NS = 2000 };
    static double x[NS], v[NS];
    char path[128], why[256];
    setup();
    snprintf(path, sizeof path, "%s/p1.png", dir);
    alarm(20); /* a hang fails here, not at ctest's timeout */
    for (int same = 0; same < 2; same++) {
        for (int i = 0; i < NS; i++) {
            x[i] = 1.28440827724 + (same ? 0.0 : (i % 7) * 2.2e-16);
            v[i] = -0.000819954217852 + (same ? 0.0 : (i % 5) * 1e-19);
        }
        plot_xy p = {"test: Poincaré map", "x_n  (b_c)", "x_n'  (b_c ω_n)", x, v, NS, 1, 1.0,
                     1, {0, NULL, 0}, {0, NULL, 0}, "P1", {"png", {NULL, NULL, NULL, NULL}}, 0};
        ASSERT_EQ_INT(plot_xy_write(path, &p, why, sizeof why), 0);
        cairo_surface_t *s = cairo_image_surface_create_from_png(path);
        ASSERT_EQ_INT(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
        /* the dot drawn: pixels of the data colour near the frame's middle */
        int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
        int st = cairo_image_surface_get_stride(s), blue = 0;
        const unsigned char *d = cairo_image_surface_get_data(s);
        for (int yy = h / 4; d && yy < 3 * h / 4; yy++)
            for (int xx = w / 4; xx < 3 * w / 4; xx++) {
                const unsigned char *px_ = d + yy * st + 4 * xx; /* B G R A */
                blue += px_[0] > 150 && px_[2] < 120;
            }
        if (blue == 0)
            TEST_FAIL_("no dot in the middle of the figure (same = %d)", same);
        cairo_surface_destroy(s);
    }
    alarm(0);
    unlink(path);
    rmdir(dir);
}

/* The y axis title keeps clear of long tick labels: a Poincare map of
 * velocities near -0.0008 (labels -0.00085, ...) had its title written
 * over them. Drawn with and without the title: the pixels the title adds
 * all lie left of the tick labels' leftmost ink, with a gap. */
static void test_ylabel_clear_of_ticks(void)
{
    enum { NS = 300 };
    static double x[NS], v[NS];
    char path[2][128], why[256];
    setup();
    for (int i = 0; i < NS; i++) {
        x[i] = 1.2844 + 1e-3 * sin(0.1 * i);
        v[i] = -0.00082 + 1.2e-4 * cos(0.1 * i);
    }
    cairo_surface_t *s[2];
    for (int t = 0; t < 2; t++) {
        snprintf(path[t], sizeof path[t], "%s/yl%d.png", dir, t);
        plot_xy p = {"test: Poincaré map", "x_n  (b_c)", t ? "x_n'  (b_c ω_n)" : "", x, v, NS,
                     1, 1.0, 1, {0, NULL, 0}, {0, NULL, 0}, NULL,
                     {"png", {NULL, NULL, NULL, NULL}}, 0};
        ASSERT_EQ_INT(plot_xy_write(path[t], &p, why, sizeof why), 0);
        s[t] = cairo_image_surface_create_from_png(path[t]);
        ASSERT_EQ_INT(cairo_surface_status(s[t]), CAIRO_STATUS_SUCCESS);
        unlink(path[t]);
    }
    int w = cairo_image_surface_get_width(s[0]), h = cairo_image_surface_get_height(s[0]);
    int st = cairo_image_surface_get_stride(s[0]);
    const unsigned char *a = cairo_image_surface_get_data(s[0]), *b = cairo_image_surface_get_data(s[1]);
    int label_left = w, title_right = -1;
    for (int yy = 100; a && b && yy < h - 100; yy++)
        for (int xx = 0; xx < 100; xx++) { /* left of the frame (x0 105) */
            const unsigned char *pa = a + yy * st + 4 * xx, *pb = b + yy * st + 4 * xx;
            if (pa[0] < 200 || pa[1] < 200 || pa[2] < 200)
                label_left = xx < label_left ? xx : label_left;
            if (memcmp(pa, pb, 4))
                title_right = xx > title_right ? xx : title_right;
        }
    ASSERT_TRUE(title_right >= 0);  /* the title was drawn */
    ASSERT_TRUE(label_left < w);    /* and so were the labels */
    if (!(title_right + 2 < label_left))
        TEST_FAIL_("the y axis title reaches x = %d px, the tick labels start at %d px",
                   title_right, label_left);
    cairo_surface_destroy(s[0]);
    cairo_surface_destroy(s[1]);
    rmdir(dir);
}

/* A sweep of one point (--from 1 --to 1 --points 1): its dot in the
 * middle of the frame, not on its left edge in an axis invented as 1 ... 2,
 * and its min x_n drawn as a dot (a line of one point drew nothing). */
static void test_single_point(void)
{
    static wg_point up[1], down[1];
    setup();
    memset(up, 0, sizeof up);
    up[0].value = 1.0;
    up[0].regime = WG_REGIME_PERIODIC;
    up[0].period = 1;
    up[0].min_xn = 0.5;
    up[0].nsec = 1;
    up[0].xn[0] = 1.2;
    down[0] = up[0];
    char path[128], why[256];
    snprintf(path, sizeof path, "%s/one.png", dir);
    plot_bif pb = {"test: one point", "ω  (-)", up, down, 1, 1, 1.0, NULL, 0,
                   {0, NULL, 0}, {0, NULL, 0}, {"png", {"caption", NULL, NULL, NULL}}};
    ASSERT_EQ_INT(plot_bifurcation(path, &pb, why, sizeof why), 0);
    cairo_surface_t *s = cairo_image_surface_create_from_png(path);
    ASSERT_EQ_INT(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
    int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
    int st = cairo_image_surface_get_stride(s);
    const unsigned char *d = cairo_image_surface_get_data(s);
    long n[2] = {0, 0}, sx[2] = {0, 0}; /* coloured pixels in the top / bottom half */
    for (int yy = 150; d && yy < h - 120; yy++)
        for (int xx = 95; xx < w - 110; xx++) {
            const unsigned char *q = d + yy * st + 4 * xx; /* B G R */
            int coloured = abs(q[0] - q[2]) > 60; /* the up blue or the down red */
            int half = yy > h * 0.62;
            n[half] += coloured, sx[half] += coloured ? xx : 0;
        }
    ASSERT_TRUE(n[0] > 0 && n[1] > 0);
    for (int k = 0; k < 2; k++) {
        double mx = n[k] ? (double)sx[k] / n[k] : 0.0;
        if (!(fabs(mx - 0.5 * (90 + 1300)) < 30))
            TEST_FAIL_("panel %d: the point drawn at x = %.0f px, the frame's middle is 695", k, mx);
    }
    cairo_surface_destroy(s);
    unlink(path);
    rmdir(dir);
}

/* Points not measured (a rig's refused values: regime none, no section,
 * min x_n NAN) break the min x_n line: it dived to the panel's floor at
 * them. Every coloured pixel of the lower panel lies on the measured
 * points' height (min x_n 0.5 throughout). */
static void test_unmeasured_break_the_line(void)
{
    static wg_point up[NPTS], down[NPTS];
    setup();
    make_points(up, down, 0);
    for (int i = 0; i < NPTS; i++) /* period 1: white cells, only the data coloured */
        up[i].regime = down[i].regime = WG_REGIME_PERIODIC, up[i].period = down[i].period = 1;
    for (int i = 8; i < 12; i++)
        for (wg_point *p = &up[i]; p; p = p == &up[i] ? &down[i] : NULL) {
            double v = p->value;
            memset(p, 0, sizeof *p);
            p->value = v, p->min_xn = p->max_xn = p->lle = NAN;
            ASSERT_TRUE(!wg_point_measured(p));
        }
    cairo_surface_t *s = draw("unmeasured", up, down);
    int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
    int st = cairo_image_surface_get_stride(s);
    const unsigned char *d = cairo_image_surface_get_data(s);
    long rows[1100] = {0}, n = 0;
    for (int yy = (int)(h * 0.62); d && yy < h - 120 && yy < 1100; yy++)
        for (int xx = 95; xx < w - 110; xx++) {
            const unsigned char *q = d + yy * st + 4 * xx; /* B G R */
            if (abs(q[0] - q[2]) > 60) /* the up blue or the down red */
                rows[yy]++, n++;
        }
    int top = 0;
    for (int yy = 0; yy < 1100; yy++)
        top = rows[yy] > rows[top] ? yy : top;
    long off = 0;
    for (int yy = 0; yy < 1100; yy++)
        off += abs(yy - top) > 3 ? rows[yy] : 0;
    printf("lower panel: %ld coloured pixels, %ld off the line at y = %d\n", n, off, top);
    ASSERT_TRUE(n > 0);
    ASSERT_EQ_INT(off, 0);
    cairo_surface_destroy(s);
    rmdir(dir);
}

/* Axis ticks: k * step, each once, at most PD_TICKS_MAX, labelled with
 * the digits that tell them apart. */
static void test_ticks(void)
{
    double t[PD_TICKS_MAX];
    char lab[PD_TICKS_MAX][PD_TICK_LABEL];
    int n = pd_ticks(0.0, 2.5, 0.2, t, lab);
    ASSERT_EQ_INT(n, 13);
    ASSERT_STR(lab[0], "0");
    ASSERT_STR(lab[3], "0.6"); /* 3 * 0.2 = 0.6000000000000001 */
    ASSERT_STR(lab[12], "2.4");
    /* a zoom into the period-doubling cascade: ten distinct labels */
    n = pd_ticks(1.3788, 1.37881, 1e-6, t, lab);
    ASSERT_EQ_INT(n, 11);
    ASSERT_STR(lab[1], "1.378801");
    for (int i = 1; i < n; i++)
        if (!strcmp(lab[i], lab[i - 1]))
            TEST_FAIL_("ticks %d and %d both labelled %s", i - 1, i, lab[i]);
    n = pd_ticks(1.0, 1.0000001, 1e-8, t, lab);
    ASSERT_TRUE(n == 10 || n == 11);
    ASSERT_STR(lab[1], "1.00000001");
    /* a step under the values' ulp: ends, each value once */
    double x = 1.28440827724;
    n = pd_ticks(x - 1e-15, x + 1e-15, 1e-17, t, lab);
    ASSERT_TRUE(n >= 1 && n <= PD_TICKS_MAX);
    for (int i = 1; i < n; i++)
        ASSERT_TRUE(t[i] > t[i - 1]);
    ASSERT_EQ_INT(pd_ticks(0.0, 1.0, 0.0, t, lab), 0);
    ASSERT_EQ_INT(pd_ticks(0.0, 1.0, NAN, t, lab), 0);
    ASSERT_EQ_INT(pd_ticks(0.0, INFINITY, 0.1, t, lab), 0);
}

/* Red-orange pixels (the down sweep's colour: R high, B low) and blue ones
 * (the up sweep's) of a figure. */
static void count_colours(cairo_surface_t *s, long *red, long *blue)
{
    int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
    int st = cairo_image_surface_get_stride(s);
    const unsigned char *d = cairo_image_surface_get_data(s);
    *red = *blue = 0;
    for (int y = 0; d && y < h; y++)
        for (int x = 0; x < w; x++) {
            const unsigned char *q = d + y * st + 4 * x; /* B G R A */
            *red += q[2] > 170 && q[0] < 90 && q[1] < 120;
            *blue += q[0] > 150 && q[2] < 120;
        }
}

/* wgrig's impacts figure: an up and a down sweep told apart (one line ran
 * up and back down in one colour, no markers): split draws the down sweep
 * in its own colour, with rings, and a legend; without split, one colour. */
static void test_split_sweeps(void)
{
    enum { N = 20 };
    double x[N], y[N];
    char path[128], why[256];
    setup();
    for (int i = 0; i < N / 2; i++) {
        x[i] = 0.5 + 0.1 * i, y[i] = i >= 5 ? 1.0 : 0.0;                       /* up */
        x[N / 2 + i] = 1.4 - 0.1 * i, y[N / 2 + i] = 1.4 - 0.1 * i >= 0.8 ? 1.0 : 0.0; /* down */
    }
    long red[2], blue[2];
    for (int split = 0; split < 2; split++) {
        snprintf(path, sizeof path, "%s/split%d.png", dir, split);
        plot_xy p = {.title = "test: impacts", .xlabel = "omega", .ylabel = "impacts", .x = x,
                     .y = y, .n = N, .pg = {"png", {NULL, NULL, NULL, NULL}},
                     .split = split ? N / 2 : 0};
        ASSERT_EQ_INT(plot_xy_write(path, &p, why, sizeof why), 0);
        cairo_surface_t *s = cairo_image_surface_create_from_png(path);
        ASSERT_EQ_INT(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
        count_colours(s, &red[split], &blue[split]);
        cairo_surface_destroy(s);
        unlink(path);
    }
    rmdir(dir);
    printf("down-sweep pixels: %ld unsplit, %ld split; up-sweep pixels %ld, %ld\n", red[0], red[1],
           blue[0], blue[1]);
    ASSERT_EQ_INT(red[0], 0);
    ASSERT_TRUE(red[1] > 500); /* its line, 10 rings and the legend's */
    ASSERT_TRUE(blue[1] > 300);
}

/* The text of file path (at most len - 1 bytes) into buf. */
static void slurp(const char *path, char *buf, size_t len)
{
    FILE *f = fopen(path, "r");
    ASSERT_TRUE(f != NULL);
    size_t n = fread(buf, 1, len - 1, f);
    buf[n] = 0;
    fclose(f);
}

/* A run with no per-point settle and record (wgrig --ramp) says what it
 * did in the diagram's caption (sweep_study.run): it said "transient 300
 * periods (+ up to 3 x 300 while no period is found), 128 periods
 * recorded", the options' defaults, which a ramp never used. */
static void test_run_caption(void)
{
    static char svg[1 << 20];
    wg_point up[NPTS], down[NPTS];
    char prefix[128], path[160], why[256];
    setup();
    make_points(up, down, 0);
    wg_sweep_opts o;
    wg_sweep_opts_default(&o);
    wg_chain ch = {.param = WG_P_OMEGA, .v0 = 1.0, .v1 = 1.4, .npts = NPTS, .dir = 1,
                   .param2 = -1, .pts = up, .ndone = NPTS};
    wg_params_default(&ch.base);
    const char *run = "ramp ω 1 → 1.4 over 2 s simulated (≈ 12000 mesh periods), every "
                      "section binned onto 21 values";
    snprintf(prefix, sizeof prefix, "%s/run", dir);
    snprintf(path, sizeof path, "%s.svg", prefix);
    for (int k = 0; k < 2; k++) {
        sweep_study st = {.scene = "test", .param = WG_P_OMEGA, .gparam = -1, .ngroups = 1,
                          .b = 1, .o = &o, .scene_p = &ch.base, .format = "svg",
                          .run = k ? run : NULL};
        st.g[0] = (sweep_group){0, &ch, NULL};
        ASSERT_EQ_INT(out_pngs(prefix, &st, NULL, why, sizeof why), 0);
        slurp(path, svg, sizeof svg);
        unlink(path);
        if (k) {
            ASSERT_TRUE(strstr(svg, "steps per mesh period, ramp ω 1 → 1.4 over 2 s simulated")
                        != NULL);
            ASSERT_TRUE(strstr(svg, "every section binned onto 21 values") != NULL);
            ASSERT_TRUE(strstr(svg, "transient") == NULL && strstr(svg, "recorded") == NULL);
        } else {
            ASSERT_TRUE(strstr(svg, "transient 300 periods") != NULL);
        }
    }
    rmdir(dir);
}

/* A continuation figure's labels over a curve: eight events at one omega,
 * their markers 20 px above a horizontal branch, so that the stacked labels
 * (right and left of the markers at -10, +6, -24 and +20 px) put the last
 * two across the branch. Every label pixel (dark red) keeps a white pixel
 * between it and the branch (no black pixel among its 8 neighbours): each
 * label has a halo. Without one (tried): 184 black neighbours. */
enum { CONT_NB = 12, CONT_NE = 8 };

/* The branch runs from x_n 0 up to 2 and down to a flat 1.0 from omega 0.6
 * to 1.5 (the y range -0.1 ... 2.1 over the frame's 540 px); the events'
 * markers sit 20 px above the flat part. */
static void cont_fixture(wg_cont_point pt[CONT_NB], wg_bif bif[CONT_NE])
{
    for (int i = 0; i < CONT_NB; i++) {
        memset(&pt[i], 0, sizeof pt[i]);
        pt[i].period = 1, pt[i].stable = 1, pt[i].index = i;
        pt[i].value = i < 2 ? 0.5 + 0.05 * i : 0.6 + 0.09 * (i - 2);
        pt[i].xnsec[0] = i == 0 ? 0.0 : i == 1 ? 2.0 : 1.0;
        pt[i].qmin[WG_C_MESH] = 0.5;
    }
    for (int e = 0; e < CONT_NE; e++) {
        memset(&bif[e], 0, sizeof bif[e]);
        bif[e].kind = e % 2 ? WG_BIF_PD : WG_BIF_FOLD;
        bif[e].period = 1;
        bif[e].value = 1.0 + 1e-5 * e;
        bif[e].xn = 1.0 + 20.0 * 2.2 / 540;
        bif[e].min_xn = 0.5;
    }
}

/* BGRA in memory on this little-endian host */
static int is_red(const unsigned char *p) { return p[2] > 100 && p[1] < 70 && p[0] < 70; }
static int is_black(const unsigned char *p) { return p[2] < 90 && p[1] < 90 && p[0] < 90; }

/* In the top frame (y 140 ... 680) of image d (stride st): the row with the
 * most black pixels (the flat branch), the label pixels within 2 px of it
 * (*across), and the black neighbours of label pixels (*touching). */
static void cont_label_pixels(const unsigned char *d, int st, int *yline, int *across,
                              int *touching)
{
    int most = 0;
    *yline = -1, *across = 0, *touching = 0;
    for (int y = 141; y < 679; y++) {
        int n = 0;
        for (int x = 300; x < 1290; x++)
            n += is_black(d + y * st + 4 * x);
        if (n > most)
            most = n, *yline = y;
    }
    if (most <= 500) /* no line drawn across the frame */
        *yline = -1;
    for (int y = 141; y < 679 && *yline >= 0; y++)
        for (int x = 91; x < 1299; x++) {
            if (!is_red(d + y * st + 4 * x))
                continue;
            *across += abs(y - *yline) <= 2;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++)
                    *touching += is_black(d + (y + dy) * st + 4 * (x + dx));
        }
}

static void test_cont_labels_over_curves(void)
{
    static wg_cont_point pt[CONT_NB];
    static wg_bif bif[CONT_NE];
    char path[128], why[256];
    setup();
    cont_fixture(pt, bif);
    cont_result r = {.pt = pt, .npt = CONT_NB, .ptcap = CONT_NB, .bif = bif, .nbif = CONT_NE,
                     .bifcap = CONT_NE};
    plot_cont pc = {.title = "test: labels", .caption = {"caption", NULL, NULL},
                    .xlabel = "ω  (-)", .xlo = 0.5, .xhi = 1.5, .b = 0.1, .r = &r,
                    .format = "png"};
    snprintf(path, sizeof path, "%s/cont.png", dir);
    ASSERT_EQ_INT(plot_continuation(path, &pc, why, sizeof why), 0);
    cairo_surface_t *sf = cairo_image_surface_create_from_png(path);
    ASSERT_EQ_INT(cairo_surface_status(sf), CAIRO_STATUS_SUCCESS);
    unlink(path);
    rmdir(dir);
    cairo_surface_flush(sf);
    int yline, across, touching;
    cont_label_pixels(cairo_image_surface_get_data(sf), cairo_image_surface_get_stride(sf),
                      &yline, &across, &touching);
    cairo_surface_destroy(sf);
    if (yline < 0)
        TEST_FAIL_("no branch found in the top frame");
    else if (!across)
        TEST_FAIL_("no label crosses the branch at y = %d px: the test no longer tries", yline);
    else if (touching)
        TEST_FAIL_("label pixels have %d black neighbours on the branch (no halo)", touching);
}

TEST_MAIN(TEST(test_ticks), TEST(test_split_sweeps), TEST(test_run_caption),
          TEST(test_repeated_sections_drawn_once),
          TEST(test_near_sections_both_drawn),
          TEST(test_each_point_its_own_spots), TEST(test_poincare_of_period_one),
          TEST(test_ylabel_clear_of_ticks), TEST(test_single_point),
          TEST(test_unmeasured_break_the_line), TEST(test_cont_labels_over_curves))
