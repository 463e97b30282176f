/* proc_status.h - one "Field: N kB" line of /proc/PID/status, for the test
 * programs that watch memory (bench_long its own RssAnon, wgfuzz the
 * daemon's VmRSS). */
#ifndef WG_PROC_STATUS_H
#define WG_PROC_STATUS_H

#include <stdio.h>
#include <string.h>
#include <sys/types.h>

/* Field's value in kB for process pid (0: this process), or -1 if unknown. */
static inline long proc_status_kb(pid_t pid, const char *field)
{
    char path[64], line[256];
    size_t n = strlen(field);
    long kb = -1;
    if (pid > 0)
        snprintf(path, sizeof path, "/proc/%d/status", (int)pid);
    else
        snprintf(path, sizeof path, "/proc/self/status");
    FILE *f = fopen(path, "r");
    while (f && fgets(line, sizeof line, f))
        if (strncmp(line, field, n) == 0 && line[n] == ':') {
            if (sscanf(line + n + 1, "%ld", &kb) != 1)
                kb = -1;
            break;
        }
    if (f)
        fclose(f);
    return kb;
}

#endif
