/* sweep_out.h - a sweep study in memory and its writers: CSV of points,
 * long CSV of Poincare values, JSON, PNGs (the Markdown transitions table
 * is sweep_md.h). Shared by wgsweep and wgrig. Writers return 0 or -1 with
 * why. */
#ifndef WG_SWEEP_OUT_H
#define WG_SWEEP_OUT_H

#include <stdio.h>
#include "units.h"
#include "wormgear/wg_sweep.h"

enum { STUDY_MAX_GROUPS = 64, STUDY_MAX_TRANS = 512 };

/* One value of the group parameter: its up and down chains (either NULL). */
typedef struct sweep_group {
    double gval;
    wg_chain *up, *down;
} sweep_group;

struct cont_bifs;

/* A 1-D study: sweeps of `param` for each group value of `gparam`. */
typedef struct sweep_study {
    const char *scene;
    const char *command;     /* the command line, for the record */
    const char *source;      /* points read from this CSV (NULL: computed) */
    int param, gparam;       /* gparam -1: a single group */
    int ngroups;
    sweep_group g[STUDY_MAX_GROUPS];
    const struct cont_bifs *exact[STUDY_MAX_GROUPS]; /* wgcont's bifurcations per group
                                (NULL: none): the table's "exact (continuation)" column */
    double b;                /* backlash of the scene */
    const wg_sweep_opts *o;
    int partial;             /* interrupted: some chains incomplete */
    double wall_s;
    int threads, ranks;
    int pair;                /* chains each thread advanced at once (--pair) */
    const wg_params *scene_p; /* the scene's own values, for the figures' captions
                                (NULL: no "set away" line) */
    units_scale us;          /* the scene's scale: the figures' Hz and µm */
    const char *format;      /* figures: "png" (NULL too), "svg" or "pdf" */
    const char *run;         /* what the run did, for the captions and the .md, where it
                                had no per-point transient and record (wgrig --ramp);
                                NULL: o's transient and record */
} sweep_study;

/* The columns of a points CSV after [GROUP,]dir,index,PARAM, in the order
 * out_points_csv writes them; load_points_csv reads them back. */
enum { OUT_POINT_NCOLS = 30 };
extern const char *const out_point_cols[OUT_POINT_NCOLS];

/* Points of every chain, one row each (CSV). */
int out_points_csv(const char *path, const sweep_study *st, char *why, size_t whylen);

/* Poincare values: group,dir,index,value,k,x_n,dx_n (CSV, long form). */
int out_poincare_csv(const char *path, const sweep_study *st, char *why, size_t whylen);

/* Everything (options, points with Poincare values and multipliers,
 * transitions) as JSON. */
int out_json(const char *path, const sweep_study *st, char *why, size_t whylen);

/* The files a run wrote, for the line that tells the user: "a.csv, b.png". */
typedef struct out_files {
    char list[4096];
    int n;
} out_files;

/* Add path to the list (NULL-safe: files may be NULL). */
void out_files_add(out_files *files, const char *path);

/* "NAME-V" for file names: the parameter and its value (%.15g: the digits
 * given, 1.37880005 not 1.3788), no '=' (a shell and a URL take it as it
 * is). Returns buf. */
const char *out_tag(char *buf, size_t len, const char *name, double v);

/* One bifurcation diagram per group: prefix.png, or prefix-NAME-V.png
 * (.svg, .pdf by st->format), with the caption of plot_text.h; each path
 * written is added to files (may be NULL). */
int out_pngs(const char *prefix, const sweep_study *st, out_files *files, char *why,
             size_t whylen);

/* The study's files: PREFIX.csv, PREFIX-poincare.csv, PREFIX.md, with
 * json PREFIX.json, with figures out_pngs' diagrams; with threads > 1 the
 * figures (or, without them, the JSON) are written on another thread
 * while this one writes the rest. Listed on files in that order, each once
 * written. On a failure every failed file's message goes to why ("; "
 * between) and -1 is returned; the others are still written. */
int out_study(const char *prefix, const sweep_study *st, int json, int figures, int threads,
              out_files *files, char *why, size_t whylen);

/* 2-D map: rows as CSV (row value, x value, regime, ...). */
int out_map_csv(const char *path, const wg_chain *rows, int nrows, char *why, size_t whylen);

/* Label of a point: "P1", "P2", "P? (n>32)", "quasi", "chaos", "-". */
const char *out_label(const wg_point *p, char *buf, size_t len);

/* The name of parameter id, "?" if there is none. */
const char *out_pname(int id);

/* The backlash of group g: the scene's, the group's value under --values
 * b=..., NAN where b is the swept parameter (each point's value). */
double out_group_b(const sweep_study *st, const sweep_group *g);

/* Open path for writing: the file, or NULL with "cannot write PATH" in why. */
FILE *out_open(const char *path, char *why, size_t whylen);

/* Close f: 0, or -1 with "error writing PATH" in why when a write or the
 * close failed. */
int out_close(FILE *f, const char *path, char *why, size_t whylen);

#endif
