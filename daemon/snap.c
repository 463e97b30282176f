/* snap.c - snapshot files for save/restore: names, the state directory,
 * reading only regular files of a bounded size, atomic writes, and the
 * removal at start of the temporary files a killed save left. The text
 * inside is the library's (wg_snapshot.h). */
#include "snap.h"

#include "wormgear/wg_file.h"
#include "wormgear/wg_status.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int snap_name_ok(const char *name, char *why, size_t whylen)
{
    size_t n = strlen(name);
    int ok = n >= 1 && n <= 64 && name[0] != '.' && !strstr(name, "..");
    for (size_t i = 0; ok && i < n; i++) {
        char c = name[i];
        ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
             c == '_' || c == '-' || c == '.';
    }
    if (!ok) { /* quoted printable only: a refused name may hold anything */
        char q[68];
        size_t i = 0;
        for (; name[i] && i < 64; i++)
            q[i] = name[i] > 0x20 && name[i] < 0x7f ? name[i] : '?';
        snprintf(q + i, sizeof q - i, "%s", name[i] ? "..." : "");
        snprintf(why, whylen, "snapshot name '%s' (%zu bytes) refused: use 1-64 of "
                              "[A-Za-z0-9_.-], not starting with '.', no '/' or '..'", q, n);
    }
    return ok ? WG_OK : WG_EINVAL;
}

void snap_take(snap *s, const wg_sim *sim, const char *scene)
{
    memset(s, 0, sizeof *s);
    snprintf(s->scene, sizeof s->scene, "%s", scene);
    wg_sim_snapshot(sim, &s->w);
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

/* ---- writing ---------------------------------------------------------------- */

/* fsync the directory, so that a rename in it survives a crash. */
static int sync_dir(const char *dir)
{
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0)
        return -1;
    int rc = fsync(fd);
    int e = errno;
    close(fd);
    errno = e;
    return rc;
}

/* text to a fresh temporary file beside path (never one that was there:
 * removed first, then created exclusively, links not followed), synced,
 * renamed over path: a reader sees the old file or the new one, whole. */
static int write_atomic(const char *dir, const char *path, const char *text, size_t n,
                        char *why, size_t whylen)
{
    char tmp[700];
    snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
    unlink(tmp);
    int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0640);
    if (fd < 0) {
        snprintf(why, whylen, "cannot write %s: %s", tmp, strerror(errno));
        return WG_EIO;
    }
    int e = wg_file_write_all(fd, text, n);
    int bad = e != 0 || fsync(fd) != 0;
    if (bad && !e)
        e = errno;
    if (close(fd) != 0 && !bad) {
        bad = 1;
        e = errno;
    }
    if (bad || rename(tmp, path) != 0) {
        snprintf(why, whylen, "cannot write %s: %s", path, strerror(bad ? e : errno));
        unlink(tmp);
        return WG_EIO;
    }
    if (sync_dir(dir) != 0) {
        snprintf(why, whylen, "wrote %s, but cannot sync %s (it may not survive a crash): %s",
                 path, dir, strerror(errno));
        return WG_EIO;
    }
    return WG_OK;
}

int snap_write(const snap *s, const char *dir, const char *name, char *path, size_t pathlen,
               char *why, size_t whylen)
{
    char text[WG_SNAPSHOT_MAX];
    int rc = file_path(path, pathlen, dir, name, why, whylen);
    if (rc)
        return rc;
    int n = wg_snapshot_format(&s->w, s->scene, text, sizeof text, why, whylen);
    if (n < 0)
        return n;
    if (mkdir(dir, 0750) != 0 && errno != EEXIST) {
        snprintf(why, whylen, "cannot create state directory %s: %s", dir, strerror(errno));
        return WG_EIO;
    }
    return write_atomic(dir, path, text, (size_t)n, why, whylen);
}

/* ---- reading ---------------------------------------------------------------- */

int snap_read(snap *s, const char *dir, const char *name, char *why, size_t whylen)
{
    char path[600];
    int rc = file_path(path, sizeof path, dir, name, why, whylen);
    if (rc)
        return rc;
    memset(s, 0, sizeof *s);
    return wg_snapshot_load(path, &s->w, s->scene, sizeof s->scene, why, whylen);
}

/* ---- start-up: the directory, temporary files of killed saves ------------------------ */

static const char DIR_RULE[] = "state_dir must be a directory this process can write, or "
                               "one it can make";

/* An existing path as the state directory: a directory we may write and
 * enter (access: a read-only file system says EROFS even to root). */
static int dir_usable(const char *dir, const struct stat *st, char *why, size_t whylen)
{
    if (!S_ISDIR(st->st_mode)) {
        snprintf(why, whylen, "state dir %s is not a directory (%s)", dir, DIR_RULE);
        return WG_EIO;
    }
    if (access(dir, W_OK | X_OK) != 0) {
        snprintf(why, whylen, "state dir %s is not writable: %s (%s)", dir, strerror(errno),
                 DIR_RULE);
        return WG_EIO;
    }
    return WG_OK;
}

/* The directory dir would be made in ("." for a bare name). */
static void parent_of(const char *dir, char *out, size_t len)
{
    size_t n = strlen(dir);
    while (n > 1 && dir[n - 1] == '/') /* "a/b/" is "a/b" */
        n--;
    while (n > 0 && dir[n - 1] != '/')
        n--;
    while (n > 1 && dir[n - 1] == '/')
        n--;
    snprintf(out, len, "%.*s", (int)n, n ? dir : ".");
}

/* Why dir's parent cannot hold it ("" when it can). */
static const char *parent_unfit(const char *parent)
{
    struct stat st;
    if (stat(parent, &st) != 0)
        return strerror(errno);
    if (!S_ISDIR(st.st_mode))
        return "not a directory";
    return access(parent, W_OK | X_OK) != 0 ? strerror(errno) : "";
}

int snap_dir_check(const char *dir, int make, int *state, char *why, size_t whylen)
{
    struct stat st;
    char parent[600];
    *state = SNAP_DIR_OK;
    if (stat(dir, &st) == 0)
        return dir_usable(dir, &st, why, whylen);
    if (errno != ENOENT) {
        snprintf(why, whylen, "state dir %s: %s (%s)", dir, strerror(errno), DIR_RULE);
        return WG_EIO;
    }
    parent_of(dir, parent, sizeof parent);
    const char *unfit = parent_unfit(parent);
    if (*unfit) {
        snprintf(why, whylen, "state dir %s does not exist, and cannot be made in %s: %s (%s)",
                 dir, parent, unfit, DIR_RULE);
        return WG_EIO;
    }
    *state = SNAP_DIR_ABSENT;
    if (!make)
        return WG_OK;
    if (mkdir(dir, 0750) != 0) { /* made meanwhile by another: judge what is there */
        int e = errno;
        if (e == EEXIST && stat(dir, &st) == 0) {
            *state = SNAP_DIR_OK;
            return dir_usable(dir, &st, why, whylen);
        }
        snprintf(why, whylen, "cannot make state dir %s: %s (%s)", dir, strerror(e), DIR_RULE);
        return WG_EIO;
    }
    *state = SNAP_DIR_MADE;
    return WG_OK;
}

/* NAME.wgstate.tmp.PID, a regular file, whose writer is gone (or is this
 * process, which has saved nothing yet): another daemon sharing the
 * directory may be writing its own right now. */
static int stale_tmp(int dfd, const char *name)
{
    const char *t = strstr(name, ".wgstate.tmp.");
    struct stat st;
    char *end;
    if (!t)
        return 0;
    t += strlen(".wgstate.tmp.");
    long pid = strtol(t, &end, 10);
    if (end == t || *end || *t < '1' || *t > '9' || pid <= 0)
        return 0;
    if (fstatat(dfd, name, &st, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(st.st_mode))
        return 0;
    return pid == (long)getpid() || (kill((pid_t)pid, 0) != 0 && errno == ESRCH);
}

int snap_init(const char *dir, int *removed, char *why, size_t whylen)
{
    *removed = 0;
    DIR *dp = opendir(dir);
    if (!dp) {
        if (errno == ENOENT) /* made by the first save */
            return WG_OK;
        snprintf(why, whylen, "cannot read state directory %s: %s", dir, strerror(errno));
        return WG_EIO;
    }
    struct dirent *e;
    while ((e = readdir(dp)))
        if (stale_tmp(dirfd(dp), e->d_name) && unlinkat(dirfd(dp), e->d_name, 0) == 0)
            (*removed)++;
    closedir(dp);
    return WG_OK;
}

int snap_apply(const snap *s, wg_sim *sim, char *why, size_t whylen)
{
    return wg_sim_restore(sim, &s->w, why, whylen);
}
