# args.sh - sourced by the project's scripts (tools/, tests/bench/): one rule
# for their command lines, as the programs' bench_args.h and cli.h have it.
#   args_help "$@"         --help or -h as the first argument: the calling
#                          script's header comment (its usage) on standard
#                          output, exit 0.
#   args_refuse NAME WHAT  the one refusal: "NAME: WHAT" and "(try NAME
#                          --help)" on standard error, exit 2.
#   args_none NAME "$@"    for a script that takes no arguments: --help as
#                          above, anything else refused.
#   args_int NAME OPERAND VALUE LO HI WHAT
#                          VALUE must be a whole number (digits) in [LO, HI],
#                          else "NAME: OPERAND 'VALUE': WHAT" is the refusal.
# POSIX sh; the script's own path is $0, as its caller ran it.

args_help() {
    case ${1:-} in
    -h | --help)
        sed -n '2,/^[^#]/s/^# \{0,1\}//p' "$0"
        exit 0
        ;;
    esac
}

args_refuse() {
    echo "$1: $2" >&2
    echo "(try $1 --help)" >&2
    exit 2
}

args_none() {
    _args_name=$1
    shift
    args_help "$@"
    [ $# -eq 0 ] || args_refuse "$_args_name" "takes no arguments, got '$1'"
}

args_int() {
    case $3 in
    '' | *[!0-9]*) args_refuse "$1" "$2 '$3': $6" ;;
    esac
    [ "$3" -ge "$4" ] && [ "$3" -le "$5" ] || args_refuse "$1" "$2 '$3': $6"
}
