/* wglog - record the bus to an LCM log, summarise a log of wormgeard, or
 * export its channels to CSV.
 *
 * `record` writes lcm-logger's format from a filtered socket (log_rec.h).
 * Reads the log with LCM's eventlog API; each message's type is found from
 * its fingerprint (the first 8 bytes), so any prefix works. `summary` lists
 * channels, types, message and sample counts, rates, seq gaps (dropped
 * messages), restarts and senders (bus.h: seq lines and their send clocks,
 * so a log played into a live bus is one more sender, not thousands of gaps
 * and restarts); `export` writes one CSV per
 * channel with the type's fields as columns, one row per sample for the
 * batched types (STATE, POINCARE, CONTACT). Numbers are written in the
 * shortest form that reads back exactly (0.08, not 0.080000000000000002):
 * the CSV holds exactly what was published. --units physical converts the
 * samples with the scale of the log's PARAMS (s, Hz, um, m/s, N).
 * Exit 0, 1 unreadable log, unwritable output or no channel matching --channel
 * (record: the log exists, a write failed), 2 usage error (record: a URL LCM
 * refuses, or port 0). */
#include "bus.h"
#include "bus_msg.h"
#include "cli.h"
#include "log_rec.h"
#include "log_rows.h"
#include "logrd.h"
#include "lcmtypes/wormgear_params_t.h"
#include "units.h"

#include <errno.h>
#include <lcm/eventlog.h>
#include <regex.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>

/* ---- reading ------------------------------------------------------------------- */

/* A big-endian int64 (a fingerprint, utime, seq) at p. */
static int64_t be64(const void *p) { return (int64_t)msg_be(p, 8); }

/* The file name of a channel's CSV: DIR/CHANNEL.csv, odd characters as '_',
 * and DIR/CHANNEL~2.csv ... when another channel's already has that name
 * (A/B and A_B were written into one file, interleaved). */
static FILE *open_csv(const log_run *r, const chan *self, char *path, size_t len)
{
    size_t n = (size_t)snprintf(path, len, "%s/", r->out), n0 = n;
    /* at most 200 bytes of the name: a file name has 255 (a longer channel name
     * stopped the whole export with "File name too long"); those alike in
     * their first 200 bytes go to ~2, ~3 ... */
    for (const char *s = self->name; *s && n + 16 < len && n - n0 < 200; s++)
        path[n++] = (*s == '/' || *s == '\\' || (unsigned char)*s < 0x20) ? '_' : *s;
    for (int k = 1;; k++) {
        snprintf(path + n, len - n, k == 1 ? ".csv" : "~%d.csv", k);
        int taken = 0;
        for (int i = 0; i < r->nch && !taken; i++)
            taken = &r->ch[i] != self && r->ch[i].file && !strcmp(r->ch[i].file, path);
        if (!taken)
            break;
        if (k == 1 && !r->quiet)
            fprintf(stderr, "wglog: %s: another channel's CSV has its file name; written to "
                    "the next free one\n", self->shown);
    }
    return fopen(path, "w");
}

static unsigned name_hash(const char *s)
{
    unsigned h = 2166136261u; /* FNV-1a */
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 16777619u;
    return h;
}

/* The slot of name in r->hix: its channel's, or the empty one it would take. */
static int *slot_of(log_run *r, const char *name)
{
    unsigned m = (unsigned)r->hcap - 1, i = name_hash(name) & m;
    while (r->hix[i] && strcmp(r->ch[r->hix[i] - 1].name, name))
        i = (i + 1) & m;
    return &r->hix[i];
}

/* Room in the index for one more channel (at most half full): 0, or -1. */
static int index_room(log_run *r)
{
    if (2 * (r->nch + 1) <= r->hcap)
        return 0;
    int cap = r->hcap ? 2 * r->hcap : 64, *old = r->hix, n = r->hcap;
    if (!(r->hix = calloc((size_t)cap, sizeof *r->hix)))
        return r->hix = old, -1;
    r->hcap = cap;
    for (int i = 0; i < n; i++)
        if (old[i])
            *slot_of(r, r->ch[old[i] - 1].name) = old[i];
    free(old);
    return 0;
}

/* The channel of ev, added on first sight (type from the fingerprint). By
 * name through a hash index: a log of 60,000 channels took minutes when each
 * event compared its name with every channel's. */
static chan *find_chan(log_run *r, const lcm_eventlog_event_t *ev)
{
    if (index_room(r))
        return NULL;
    int *slot = slot_of(r, ev->channel);
    if (*slot)
        return &r->ch[*slot - 1];
    if (r->nch == r->cap) {
        int cap = r->cap ? 2 * r->cap : 16;
        chan *c = realloc(r->ch, sizeof *c * (size_t)cap);
        if (!c)
            return NULL;
        r->ch = c, r->cap = cap;
    }
    chan *c = &r->ch[r->nch++];
    *c = (chan){.name = strdup(ev->channel), .type = T_UNKNOWN};
    if (!c->name)
        return r->nch--, NULL;
    *slot = r->nch;
    cli_text(c->shown, sizeof c->shown, ev->channel); /* any sender named it */
    c->hash = ev->datalen >= 8 ? be64(ev->data) : 0;
    c->type = ev->datalen >= 8 ? log_rows_type(c->hash) : T_UNKNOWN;
    c->t0 = ev->timestamp;
    return c;
}

/* Every wormgear type starts utime, seq: tell the senders apart (the log's
 * timestamp is the receiver's clock), count gaps and restarts inside each,
 * and note every sender after the first. */
static void note_seq(chan *c, const lcm_eventlog_event_t *ev)
{
    if (c->type == T_UNKNOWN || ev->datalen < 24 ||
        !strcmp(log_rows_type_name(c->type), "cmd_t"))
        return; /* cmd_t seq counts per client, not per channel */
    int64_t utime = be64((const char *)ev->data + 8), seq = be64((const char *)ev->data + 16);
    int line, rc = bus_streams_note(&c->seq, seq, utime, 0, ev->timestamp * 1e-6,
                                    ev->timestamp, &line);
    const bus_stream *l = &c->seq.s[line];
    size_t n = strlen(c->notes);
    if ((rc == BUS_NEW && c->seq.ids > 1) || rc == BUS_RESTART)
        snprintf(c->notes + n, sizeof c->notes - n, "%s%s from seq %lld at %.3f s, its clock "
                 "%+.3f s from the log's%s", n ? "; " : "", rc == BUS_NEW ? "a sender" : "a restart",
                 (long long)seq, ((double)ev->timestamp - (double)c->t0) * 1e-6, l->offset_s,
                 bus_stream_replayed(l) ? " (a replay)" : "");
}

/* A channel --channel left out, kept (the first 64) to name when nothing
 * matched. */
static void note_other(log_run *r, const char *name)
{
    char shown[96];
    cli_text(shown, sizeof shown, name);
    for (int i = 0; i < r->nothers; i++)
        if (!strcmp(r->others[i], shown))
            return;
    if (r->nothers < 64)
        memcpy(r->others[r->nothers++], shown, sizeof shown);
    else
        r->more = 1;
}

static int csv_open_max(void)
{
    struct rlimit rl;
    if (getrlimit(RLIMIT_NOFILE, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY)
        return CSV_OPEN_MAX;
    rlim_t half = rl.rlim_cur / 2;
    return half < 4 ? 4 : half < CSV_OPEN_MAX ? (int)half : CSV_OPEN_MAX;
}

/* Close c's CSV. A write to it that failed is said, once: the channel
 * writes no more rows (reopened, it would add them after a torn one, and
 * say it again at every close). 0, or 1. */
static int close_csv(chan *c)
{
    errno = 0;
    int bad = ferror(c->csv), err = errno;
    if (fclose(c->csv))
        bad = 1, err = errno;
    c->csv = NULL;
    if (bad) { /* its name and why: "error writing the CSV of X" said neither */
        c->wbad = 1;
        fprintf(stderr, "wglog: writing %s (channel %s) failed: %s: the file is incomplete\n",
                c->file ? c->file : "?", c->shown, err ? strerror(err) : "a write error");
    }
    return bad;
}

/* Close every CSV open now (each is reopened at its channel's next message). */
static void close_open(log_run *r)
{
    for (int i = 0; i < r->nopen; i++)
        r->wfail |= close_csv(&r->ch[r->open_ix[i]]);
    r->nopen = 0;
}

/* c's CSV open for its next rows: made ("w") at its first message, reopened
 * ("a") after close_open, which runs when open_max are open or the
 * descriptors run out; none for a channel whose write failed. 0, or -1
 * (said). */
static int csv_ready(log_run *r, chan *c)
{
    char path[4096] = "";
    if (c->csv || c->wbad)
        return 0;
    if (!r->open_max)
        r->open_max = csv_open_max();
    if (r->nopen == r->open_max)
        close_open(r);
    for (int again = 1; !c->csv; again = 0) {
        if (c->file)
            c->csv = fopen(c->file, "a");
        else if ((c->csv = open_csv(r, c, path, sizeof path)) && !(c->file = strdup(path)))
            fclose(c->csv), c->csv = NULL, errno = ENOMEM;
        if (c->csv || !again || r->nopen == 0 || (errno != EMFILE && errno != ENFILE))
            break;
        close_open(r); /* fewer descriptors than open_max allowed for: once more */
    }
    if (!c->csv) {
        fprintf(stderr, "wglog: cannot write %s: %s\n", c->file ? c->file : path,
                strerror(errno));
        return -1;
    }
    r->open_ix[r->nopen++] = (int)(c - r->ch);
    return 0;
}

static int event(log_run *r, const lcm_eventlog_event_t *ev)
{
    if (r->has_re && regexec(&r->re, ev->channel, 0, NULL, 0) != 0) {
        note_other(r, ev->channel);
        return 0;
    }
    chan *c = find_chan(r, ev);
    if (!c || !c->name)
        return -1;
    if (r->export_ && c->type != T_UNKNOWN && csv_ready(r, c))
        return -1;
    int n = c->type == T_UNKNOWN ? 0 : log_rows(r, c, ev);
    if (n < 0) {
        c->bad++; /* its seq is no seq either (it was noted: a false restart) */
    } else {
        c->samples += n;
        note_seq(c, ev);
    }
    c->msgs++;
    c->bytes += ev->datalen;
    c->t1 = ev->timestamp;
    return 0;
}

/* --units physical: the scale of the log's first PARAMS (the samples
 * before it are in that scale too). 0, or 1 with a message. */
static int first_scale(log_run *r)
{
    logrd log;
    if (logrd_open(&log, r->path, 1))
        return 0; /* read_log reports it */
    lcm_eventlog_event_t *ev;
    int64_t h = __wormgear_params_t_get_hash();
    while (!units_scale_ok(&r->scale) && (ev = logrd_next(&log))) {
        wormgear_params_t m;
        if (ev->datalen >= 8 && be64(ev->data) == h && /* any channel: --channel STATE too */
            bus_msg_ok(BUS_PARAMS, ev->data, ev->datalen) &&
            wormgear_params_t_decode(ev->data, 0, ev->datalen, &m) >= 0) {
            r->scale = (units_scale){m.omega_n_rad_s, m.length_m, m.mesh_stiffness_N_m};
            wormgear_params_t_decode_cleanup(&m);
        }
        lcm_eventlog_free_event(ev);
    }
    fclose(log.f);
    if (units_scale_ok(&r->scale))
        return 0;
    fprintf(stderr, "wglog: --units physical: %s has no PARAMS message, so its physical scale "
                    "(omega_n, b_c, K_m) is unknown\n", r->path);
    return 1;
}

static int read_log(log_run *r)
{
    logrd log;
    if (logrd_open(&log, r->path, 0))
        return 1;
    int rc = 0;
    lcm_eventlog_event_t *ev;
    while (!rc && (ev = logrd_next(&log))) {
        if (r->events++ == 0)
            r->t0 = ev->timestamp;
        r->t1 = ev->timestamp;
        rc = event(r, ev) ? 1 : 0;
        lcm_eventlog_free_event(ev);
    }
    if (logrd_close(&log, r->path, r->events) && !rc)
        r->damaged = 1; /* the summary of what was read still comes; exit 1 */
    return rc;
}

/* ---- output ---------------------------------------------------------------------- */

static int by_name(const void *a, const void *b)
{
    return strcmp(((const chan *)a)->name, ((const chan *)b)->name);
}

static void summary(log_run *r, FILE *f)
{
    double span = ((double)r->t1 - (double)r->t0) * 1e-6; /* any int64 stamps: no overflow */
    fprintf(f, "log %s: %ld events, %.3f s, %d channels\n", r->path, r->events, span, r->nch);
    if (r->nch > 1) /* qsort of no array (NULL) is undefined */
        qsort(r->ch, (size_t)r->nch, sizeof *r->ch, by_name);
    fprintf(f, "%-24s %-11s %8s %9s %11s %9s %5s %8s %8s %6s %7s\n", "channel", "type", "msgs",
            "samples", "bytes", "rate_hz", "gaps", "missing", "restarts", "bad", "senders");
    for (int i = 0; i < r->nch; i++) {
        const chan *c = &r->ch[i];
        double s = ((double)c->t1 - (double)c->t0) * 1e-6;
        double rate = c->msgs > 1 && s > 0 ? (c->msgs - 1) / s : 0;
        fprintf(f, "%-24s %-11s %8ld %9ld %11lld %9.2f %5ld %8ld %8ld %6ld %7ld\n", c->shown,
                c->type == T_UNKNOWN ? "unknown" : log_rows_type_name(c->type), c->msgs,
                c->samples, c->bytes, rate, c->seq.gaps, c->seq.missing, c->seq.restarts, c->bad,
                c->seq.senders);
    }
    for (int i = 0; i < r->nch; i++)
        if (r->ch[i].notes[0])
            fprintf(f, "note: %s: %s\n", r->ch[i].shown, r->ch[i].notes);
}

static int close_all(log_run *r)
{
    int rc = r->wfail;
    r->nopen = 0;
    for (int i = 0; i < r->nch; i++) {
        chan *c = &r->ch[i];
        if (c->csv && close_csv(c))
            rc = 1;
        if (r->export_ && c->bad && c->type != T_UNKNOWN) { /* they went without a word */
            fprintf(stderr, "wglog: %s: %ld of %ld messages are not whole %s messages (their "
                    "bytes fail the check; `wglog summary` counts them as bad): left out of %s\n",
                    c->shown, c->bad, c->msgs, log_rows_type_name(c->type),
                    c->file ? c->file : "its CSV");
            rc = 1;
        }
        if (r->export_ && c->type == T_UNKNOWN && !r->quiet)
            fprintf(stderr, "wglog: %s: not a wormgear type (fingerprint %016llx), skipped\n",
                    c->shown, (unsigned long long)c->hash);
    }
    return rc;
}

static void usage(FILE *f)
{
    fprintf(f,
            "usage: wglog record LOG [options]\n"
            "       wglog summary LOG [options]\n"
            "       wglog export LOG [options]\n"
            "Record the bus to LOG (LCM's log format, as lcm-logger writes it; lcm-logplayer\n"
            "plays it back), until SIGINT (Ctrl-C), SIGTERM or --duration. Unlike lcm-logger it\n"
            "filters its socket, so a hostile datagram cannot end it (lcmtypes/PROTOCOL.md).\n"
            "Summarise a log of wormgeard (channels, types, counts, rates, seq gaps), or\n"
            "export each channel to DIR/CHANNEL.csv with the type's fields as columns (one row\n"
            "per sample for STATE, POINCARE, CONTACT).\n\n"
            "      --url URL         record: LCM URL (default $WORMGEAR_URL, else\n"
            "                        %s)\n"
            "      --duration S      record: stop after S seconds (default: at SIGINT)\n"
            "      --force           record: overwrite LOG if it exists (default: refuse)\n"
            "  -o, --out DIR         export: output directory, created if missing (default .)\n"
            "  -c, --channel REGEX   only channels matching this POSIX extended regex, anchored\n"
            "                        (default: all, i.e. '.*')\n"
            "  -u, --units U         export: dimensionless (default) or physical: the samples\n"
            "                        of STATE, POINCARE, CONTACT in Hz, um, m/s, N (columns\n"
            "                        f_mesh_hz, x_n_um, dx_n_m_s, F_N, x1_um ... ds_m_s,\n"
            "                        velocity_m_s), with the scale of the log's PARAMS\n"
            "  -s, --summary         export: also print the summary\n"
            "  -q, --quiet           no notes about skipped channels (record: no lines at\n"
            "                        its start and end)\n"
            "  -h, --help            this text\n\n"
            "Exit status: 0 ok, 1 unreadable log, unwritable output or no channel matching\n"
            "--channel (record: LOG exists, a write failed), 2 usage error (record: a URL\n"
            "LCM refuses).\n",
            bus_default_url());
}

#define PROG "wglog"

/* The command line: a log_run for summary and export, record's options. */
typedef struct cmdline {
    log_run r;
    log_rec_opts rec;
    int record;
    const char *export_only, *record_only; /* an option given that only they take */
} cmdline;

enum { OPT_URL = 1000, OPT_DURATION, OPT_FORCE };

static int opt_one(void *ctx, int c, const char *a)
{
    cmdline *m = ctx;
    log_run *r = &m->r;
    switch (c) {
    case 'o': r->out = a, m->export_only = "--out"; return 0;
    case 'c': r->pattern = a; return 0;
    case 's': r->also_summary = 1, m->export_only = "--summary"; return 0;
    case 'u':
        if (strcmp(a, "physical") && strcmp(a, "dimensionless"))
            return cli_usage_error(PROG, "--units '%s': dimensionless or physical", a);
        r->physical = !strcmp(a, "physical"), m->export_only = "--units";
        return 0;
    case 'q': r->quiet = m->rec.quiet = 1; return 0;
    case OPT_URL: m->rec.url = a, m->record_only = "--url"; return 0;
    case OPT_DURATION:
        m->record_only = "--duration";
        return cli_opt_num(PROG, "--duration", a, 1e-3, 1e7, "seconds, 0.001 to 1e7",
                           &m->rec.duration_s);
    case OPT_FORCE: m->rec.force = 1, m->record_only = "--force"; return 0;
    case 'h': usage(stdout); exit(0);
    default: return -1;
    }
}

static int parse(int argc, char **argv, cmdline *m)
{
    static const struct option lo[] = {{"out", 1, 0, 'o'},     {"channel", 1, 0, 'c'},
                                       {"summary", 0, 0, 's'}, {"quiet", 0, 0, 'q'}, {"units", 1, 0, 'u'},
                                       {"url", 1, 0, OPT_URL}, {"duration", 1, 0, OPT_DURATION},
                                       {"force", 0, 0, OPT_FORCE}, {"help", 0, 0, 'h'},
                                       {0, 0, 0, 0}};
    log_run *r = &m->r;
    int rc = cli_getopt(PROG, argc, argv, "o:c:u:sqh", lo, opt_one, m);
    if (rc)
        return rc;
    if (argc - optind != 2)
        return cli_usage_error(PROG, "%d argument%s: expected two, a command (record, summary or "
                               "export) and a log file", argc - optind,
                               argc - optind == 1 ? "" : "s");
    const char *cmd = argv[optind];
    if (strcmp(cmd, "record") && strcmp(cmd, "summary") && strcmp(cmd, "export"))
        return cli_usage_error(PROG, "command '%s': one of record, summary, export", cmd);
    m->record = !strcmp(cmd, "record");
    r->export_ = !strcmp(cmd, "export");
    if (m->export_only && !r->export_)
        return cli_usage_error(PROG, "%s is an option of export, not of %s", m->export_only, cmd);
    if (m->record_only && !m->record)
        return cli_usage_error(PROG, "%s is an option of record, not of %s", m->record_only, cmd);
    r->path = m->rec.path = argv[optind + 1];
    if (!m->rec.url)
        m->rec.url = bus_default_url();
    if (r->pattern) {
        char anchored[1024];
        snprintf(anchored, sizeof anchored, "^(%s)$", r->pattern);
        if (regcomp(&r->re, anchored, REG_EXTENDED | REG_NOSUB))
            return cli_usage_error(PROG, "--channel '%s': a POSIX extended regular expression",
                                   r->pattern);
        r->has_re = 1;
    }
    return 0;
}

/* --channel matched none of the log's channels: say which there are, exit 1. */
static int no_match(const log_run *r)
{
    if (!r->nothers) {
        fprintf(stderr, "wglog: %s has no events, so no channel matches --channel '%s'\n",
                r->path, r->pattern);
        return 1;
    }
    fprintf(stderr, "wglog: no channel of %s matches --channel '%s' (a regex matching the "
            "whole name); its channels include", r->path, r->pattern);
    for (int i = 0; i < r->nothers && i < 8; i++)
        fprintf(stderr, "%s %s", i ? "," : "", r->others[i]);
    if (r->nothers > 8 || r->more)
        fprintf(stderr, " and %s%d more", r->more ? "over " : "", r->nothers - 8);
    fprintf(stderr, "\n");
    return 1;
}

int main(int argc, char **argv)
{
    cmdline m = {.r = {.out = "."}};
    log_run r;
    int rc = parse(argc, argv, &m);
    if (!rc && m.record) {
        m.rec.re = m.r.has_re ? &m.r.re : NULL;
        rc = log_rec_run(&m.rec);
        if (m.r.has_re)
            regfree(&m.r.re);
        return rc;
    }
    r = m.r;
    if (!rc && r.export_ && mkdir(r.out, 0777) && errno != EEXIST) {
        fprintf(stderr, "wglog: cannot create --out directory '%s': %s\n", r.out, strerror(errno));
        rc = 1;
    }
    if (!rc && r.physical)
        rc = first_scale(&r);
    if (!rc)
        rc = read_log(&r);
    rc |= close_all(&r);
    if (!rc && r.has_re && r.nch == 0)
        rc = no_match(&r);
    if (!rc && (!r.export_ || r.also_summary))
        summary(&r, stdout); /* of what could be read, a damaged log's too */
    rc |= r.damaged;
    for (int i = 0; i < r.nch; i++)
        free(r.ch[i].name), free(r.ch[i].file);
    free(r.ch);
    free(r.hix);
    if (r.has_re)
        regfree(&r.re);
    return cli_stdout_close(PROG, rc);
}
