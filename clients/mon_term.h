/* mon_term.h - wgmon's terminal: keys read at once (no line editing, no
 * echo), the alternate screen with the cursor hidden, and both given back
 * at the end, whichever way the monitor ends. */
#ifndef WG_MON_TERM_H
#define WG_MON_TERM_H

#include <stddef.h>
#include <termios.h>

typedef struct mon_term {
    struct termios tio; /* stdin's modes before */
    int raw;            /* stdin is a terminal now in raw mode: read keys from it */
} mon_term;

/* The bytes that give the screen and the cursor back (written by the
 * caller: wgmon's go through its writer, after the last frame). */
extern const char mon_term_leave_seq[];
extern const size_t mon_term_leave_len;

/* stdin raw when it is a terminal; the alternate screen, cleared, cursor
 * hidden, written to stdout now (before any frame). */
void mon_term_enter(mon_term *t);

/* stdin's modes as they were (the screen is the caller's). */
void mon_term_restore(mon_term *t);

/* Both given back at once: the modes, then mon_term_leave_seq written to
 * stdout directly (for an end before the writer started). */
void mon_term_leave(mon_term *t);

#endif
