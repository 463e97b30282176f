/* wg_file.h - opening a file that must be a regular one.
 *
 * Every reader of a file a user names (scenes, snapshots, key files, the
 * daemon's config, logs, the CSV files the clients read back) opens it
 * here, so each refuses the same things in the same words: a directory, a
 * FIFO, a device or a socket is refused before it is opened (a FIFO would
 * block the open, a directory reads as an empty file), a file over the
 * reader's size limit is refused, and what was opened is judged again by
 * fstat (it may have been replaced in between).
 *
 * Each refusal is one sentence naming the file, with `what` (a noun such
 * as "config file"; NULL or "" for none) before its path:
 *   "cannot open config file /etc/x.conf: No such file or directory"
 *   "config file /etc/x.conf is a FIFO, not a regular file"
 *   "config file /etc/x.conf is 1048577 bytes (limit 1048576)"
 *   "cannot read config file /etc/x.conf: Input/output error"
 *   "config file /etc/x.conf grew past 1048576 bytes while it was read" */
#ifndef WG_FILE_H
#define WG_FILE_H

#include <stddef.h>
#include <stdio.h>
#include <sys/stat.h>

enum {
    WG_FILE_NOFOLLOW = 1 /* a symbolic link is refused, not followed */
};

/* A descriptor open for reading on path if it is a regular file of at most
 * max_bytes (max_bytes < 0: any size), or -1 with why; st (may be NULL)
 * gets what fstat said of the open file (its size, its mode). O_NONBLOCK
 * stays set (it changes nothing for a regular file). */
int wg_file_open(const char *path, const char *what, unsigned flags, long long max_bytes,
                 struct stat *st, char *why, size_t whylen);

/* The same, as a stdio stream; NULL with why. */
FILE *wg_file_fopen(const char *path, const char *what, unsigned flags, long long max_bytes,
                    struct stat *st, char *why, size_t whylen);

/* The whole of path (opened as wg_file_open does) in buf, which holds
 * max_bytes + 1 bytes: the number of bytes read, or -1 with why. */
long wg_file_read(const char *path, const char *what, unsigned flags, char *buf,
                  size_t max_bytes, char *why, size_t whylen);

/* Write the n bytes at buf to fd whole, again after a short write or
 * EINTR (blocking as long as fd does): 0, or the errno of the write that
 * failed (EIO for one that wrote nothing). */
int wg_file_write_all(int fd, const void *buf, size_t n);

/* Text from a file or the bus made fit for a message, in place: every
 * control byte (C0 but tab, DEL, and C1 as UTF-8 encodes it, \xc2\x80 to
 * \xc2\x9f) becomes '?'. Echoed raw, a scene's "model = \e]0;x\a" set the
 * terminal's title, and reached the journal. Returns s. */
char *wg_text_clean(char *s);

/* Said after a file's value that holds '#' and was refused: libinih (as
 * Debian builds it) ends a value at " ;", and '#' only starts a whole-line
 * comment, so "omega = 1.2 # note" read as the value "1.2 # note". */
#define WG_INI_HASH_HINT "a comment after a value starts with ';', not '#'"

/* Why a file of stat mode st_mode is not read ("is a FIFO, not a regular
 * file", ...), NULL for a regular file. */
const char *wg_file_not_regular(unsigned st_mode);

#endif
