/* wg_status.c - names of the status codes, and why a file is not read. */
#include "wormgear/wg_status.h"

#include <stddef.h>
#include <sys/stat.h>

static const struct {
    int code;
    const char *name, *str;
} codes[] = {
    {WG_OK, "OK", "success"},
    {WG_EINVAL, "EINVAL", "malformed argument"},
    {WG_ERANGE, "ERANGE", "value out of range"},
    {WG_EUNKNOWN, "EUNKNOWN", "unknown parameter or key"},
    {WG_ENONFINITE, "ENONFINITE", "non-finite or absurd state"},
    {WG_ESTABILITY, "ESTABILITY", "step too large for RK4 stability"},
    {WG_ENOMEM, "ENOMEM", "out of memory"},
    {WG_EIO, "EIO", "input/output error"},
    {WG_ESTATE, "ESTATE", "not allowed in the current state"},
    {WG_EDECODE, "EDECODE", "message could not be decoded"},
    {WG_EUNSUPPORTED, "EUNSUPPORTED", "unsupported combination"},
    {WG_EAUTH, "EAUTH", "command not authenticated"},
};

const char *wg_status_name(int code)
{
    for (unsigned i = 0; i < sizeof codes / sizeof codes[0]; i++)
        if (codes[i].code == code)
            return codes[i].name;
    return "EUNKNOWNCODE";
}

const char *wg_status_str(int code)
{
    for (unsigned i = 0; i < sizeof codes / sizeof codes[0]; i++)
        if (codes[i].code == code)
            return codes[i].str;
    return "unknown status code";
}

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
