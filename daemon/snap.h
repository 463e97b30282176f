/* snap.h - save/restore: the full simulation state and parameters in a
 * named file under the state directory.
 *
 * The text is the library's snapshot format (wormgear/wg_snapshot.h:
 * format 2, every field, hex floats, a BLAKE2b checksum), so a restore
 * continues bit-exactly where the save was taken. This module is the file
 * system's side: names are [A-Za-z0-9_.-], 1-64 characters, not starting
 * with '.' (no '/', no ".."); the file is NAME.wgstate, written to
 * NAME.wgstate.tmp.PID, synced and renamed (a reader sees the old file or
 * the new one, whole), and the directory synced. A restore reads only a
 * regular file of at most WG_SNAPSHOT_MAX bytes, never follows a symbolic
 * link, never blocks on a FIFO, and never quotes the file's content. */
#ifndef WGD_SNAP_H
#define WGD_SNAP_H

#include <stddef.h>
#include <stdint.h>

#include "wormgear/wg_sim.h"
#include "wormgear/wg_snapshot.h"

typedef struct snap {
    char scene[WG_SNAPSHOT_SCENE_MAX];
    wg_snapshot w; /* the library's run state (wg_sim_snapshot/restore) */
} snap;

/* 0 if name is an acceptable snapshot name, else WG_EINVAL with why. */
int snap_name_ok(const char *name, char *why, size_t whylen);

/* Capture sim (and the scene name) into s. */
void snap_take(snap *s, const wg_sim *sim, const char *scene);

/* Write s to dir/NAME.wgstate atomically (dir created if missing). WG_OK,
 * WG_EINVAL (name, or a state that cannot be saved) or WG_EIO with why;
 * *path receives the file name. */
int snap_write(const snap *s, const char *dir, const char *name, char *path, size_t pathlen,
               char *why, size_t whylen);

/* Read dir/NAME.wgstate into s: WG_OK; WG_EINVAL (name; text that is not a
 * whole, intact format-2 snapshot: "PATH: line 12: ..."); WG_EIO (missing,
 * unreadable, not a regular file: "PATH is a FIFO, not a regular file", or
 * larger than WG_SNAPSHOT_MAX: "PATH is 2097152 bytes (limit 8192)"). Never
 * blocks; why never quotes the file. The values are checked by snap_apply. */
int snap_read(snap *s, const char *dir, const char *name, char *why, size_t whylen);

/* What snap_dir_check found (*state). */
enum { SNAP_DIR_OK, SNAP_DIR_MADE, SNAP_DIR_ABSENT };

/* Is dir usable as the state directory, so that a save does not fail for
 * it long after the start: an existing directory this process can write
 * and enter (SNAP_DIR_OK), or, when dir does not exist, one whose parent
 * is such a directory: made now (mode 0750) when make is 1 (SNAP_DIR_MADE),
 * reported SNAP_DIR_ABSENT when 0 (--check-config changes nothing). WG_OK,
 * or WG_EIO with why (what dir is, and what is allowed). */
int snap_dir_check(const char *dir, int make, int *state, char *why, size_t whylen);

/* At start: remove the temporary files (NAME.wgstate.tmp.PID, regular
 * files only) that saves killed mid-write left in dir, those of a process
 * that no longer exists or of this one; *removed counts them. WG_OK (also
 * when dir does not exist yet), or WG_EIO with why if dir cannot be read. */
int snap_init(const char *dir, int *removed, char *why, size_t whylen);

/* Apply s to sim, atomically, every value checked as the live path would
 * (wg_sim_restore): WG_ESTATE if the model, stepper or N differ from the
 * running sim, WG_ERANGE/WG_ESTABILITY for the parameters or the ramp,
 * WG_EINVAL for the state, time, counters or statistics; sim unchanged on
 * error. */
int snap_apply(const snap *s, wg_sim *sim, char *why, size_t whylen);

#endif
