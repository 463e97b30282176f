/* wg_status.c - names of the status codes. */
#include "wormgear/wg_status.h"

#include <stddef.h>

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
