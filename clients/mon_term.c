/* mon_term.c - wgmon's terminal: see mon_term.h. */
#include "mon_term.h"

#include <stdio.h>
#include <unistd.h>

const char mon_term_leave_seq[] = "\033[?25h\033[?1049l"; /* the cursor back, the screen as it was */
const size_t mon_term_leave_len = sizeof mon_term_leave_seq - 1;

void mon_term_enter(mon_term *t)
{
    if (isatty(STDIN_FILENO) && tcgetattr(STDIN_FILENO, &t->tio) == 0) {
        struct termios r = t->tio;
        r.c_lflag &= ~(tcflag_t)(ICANON | ECHO);
        r.c_cc[VMIN] = 0;
        r.c_cc[VTIME] = 0;
        t->raw = tcsetattr(STDIN_FILENO, TCSANOW, &r) == 0;
    }
    fputs("\033[?1049h\033[?25l\033[2J", stdout);
    fflush(stdout);
}

void mon_term_restore(mon_term *t)
{
    if (t->raw)
        tcsetattr(STDIN_FILENO, TCSANOW, &t->tio);
    t->raw = 0;
}

void mon_term_leave(mon_term *t)
{
    mon_term_restore(t);
    fputs(mon_term_leave_seq, stdout);
    fflush(stdout);
}
