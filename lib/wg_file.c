/* wg_file.c - opening a file that must be a regular one (wg_file.h). */
#include "wormgear/wg_file.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

const char *wg_file_not_regular(unsigned st_mode)
{
    mode_t m = (mode_t)st_mode;
    return S_ISREG(m)    ? NULL
           : S_ISLNK(m)  ? "is a symbolic link (not followed), not a regular file"
           : S_ISDIR(m)  ? "is a directory, not a regular file"
           : S_ISFIFO(m) ? "is a FIFO, not a regular file"
           : S_ISSOCK(m) ? "is a socket, not a regular file"
           : S_ISCHR(m)  ? "is a character device, not a regular file"
           : S_ISBLK(m)  ? "is a block device, not a regular file"
                         : "is not a regular file";
}

/* "config file " before a path, or nothing. */
static const char *noun(const char *what) { return what && *what ? what : ""; }
static const char *gap(const char *what) { return what && *what ? " " : ""; }

static void cannot(const char *verb, const char *path, const char *what, int err, char *why,
                   size_t whylen)
{
    snprintf(why, whylen, "cannot %s %s%s%s: %s", verb, noun(what), gap(what), path,
             strerror(err));
}

/* A regular file within the limit, or -1 with why (its kind or size). */
static int judge(const char *path, const char *what, unsigned mode, long long size,
                 long long max_bytes, char *why, size_t whylen)
{
    const char *kind = wg_file_not_regular(mode);
    if (kind) {
        snprintf(why, whylen, "%s%s%s %s", noun(what), gap(what), path, kind);
        return -1;
    }
    if (max_bytes >= 0 && size > max_bytes) {
        snprintf(why, whylen, "%s%s%s is %lld bytes (limit %lld)", noun(what), gap(what), path,
                 size, max_bytes);
        return -1;
    }
    return 0;
}

int wg_file_open(const char *path, const char *what, unsigned flags, long long max_bytes,
                 struct stat *out, char *why, size_t whylen)
{
    int nofollow = (flags & WG_FILE_NOFOLLOW) != 0;
    struct stat st;
    if ((nofollow ? lstat(path, &st) : stat(path, &st)) != 0) {
        cannot("open", path, what, errno, why, whylen);
        return -1;
    }
    if (judge(path, what, st.st_mode, (long long)st.st_size, max_bytes, why, whylen))
        return -1;
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC | (nofollow ? O_NOFOLLOW : 0));
    if (fd < 0) {
        if (nofollow && errno == ELOOP) /* replaced by a link since the lstat */
            judge(path, what, S_IFLNK, 0, max_bytes, why, whylen);
        else
            cannot("open", path, what, errno, why, whylen);
        return -1;
    }
    if (fstat(fd, &st) != 0) {
        cannot("open", path, what, errno, why, whylen);
        close(fd);
        return -1;
    }
    if (judge(path, what, st.st_mode, (long long)st.st_size, max_bytes, why, whylen)) {
        close(fd);
        return -1;
    }
    if (out)
        *out = st;
    return fd;
}

FILE *wg_file_fopen(const char *path, const char *what, unsigned flags, long long max_bytes,
                    struct stat *st, char *why, size_t whylen)
{
    int fd = wg_file_open(path, what, flags, max_bytes, st, why, whylen);
    if (fd < 0)
        return NULL;
    FILE *f = fdopen(fd, "r");
    if (!f) {
        cannot("open", path, what, errno, why, whylen);
        close(fd);
    }
    return f;
}

long wg_file_read(const char *path, const char *what, unsigned flags, char *buf,
                  size_t max_bytes, char *why, size_t whylen)
{
    int fd = wg_file_open(path, what, flags, (long long)max_bytes, NULL, why, whylen);
    if (fd < 0)
        return -1;
    size_t n = 0;
    ssize_t k = 1;
    while (n <= max_bytes && k != 0)
        if ((k = read(fd, buf + n, max_bytes + 1 - n)) > 0)
            n += (size_t)k;
        else if (k < 0 && errno != EINTR)
            break;
    int err = errno;
    close(fd);
    if (k < 0) {
        cannot("read", path, what, err, why, whylen);
        return -1;
    }
    if (n > max_bytes) { /* grew since the fstat */
        snprintf(why, whylen, "%s%s%s grew past %zu bytes while it was read", noun(what),
                 gap(what), path, max_bytes);
        return -1;
    }
    return (long)n;
}

int wg_file_write_all(int fd, const void *buf, size_t n)
{
    const char *p = buf;
    while (n > 0) {
        ssize_t k = write(fd, p, n);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            return k < 0 ? errno : EIO;
        p += k;
        n -= (size_t)k;
    }
    return 0;
}

char *wg_text_clean(char *s)
{
    for (unsigned char *p = (unsigned char *)s; p && *p; p++)
        if ((*p < 0x20 && *p != '\t') || *p == 0x7f)
            *p = '?';
        else if (*p == 0xc2 && p[1] >= 0x80 && p[1] <= 0x9f)
            *p = '?', p[1] = '?', p++;
    return s;
}
