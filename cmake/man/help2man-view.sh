#!/bin/sh
# A granflow program as help2man reads it (cmake/Install.cmake): GRANFLOW_PROGRAM names the
# program; this prints its --version, or its --help with two changes:
#  * option and argument descriptions indented by 24 columns instead of 10, so that help2man
#    sees each as the description of the line above (it wants 20 or more) and not as more
#    option lines (lib/core/cli.cpp writes "  -o, --output <FILE>" then "          text");
#  * for a program with commands (gf-stz), after its own help one "*Command NAME*" section per
#    command its "Commands:" block lists, holding that command's help with "Options:" renamed
#    (help2man would move them into the page's OPTIONS), so that one page covers every option.
# Prints nothing and fails if any part fails, so that help2man stops instead of making a page
# without it.
set -eu
program=${GRANFLOW_PROGRAM:?GRANFLOW_PROGRAM must name the program}
case "${1:-}" in
  --version) exec "$program" --version ;;
  --help) ;;
  *) echo "usage: GRANFLOW_PROGRAM=PATH $0 --help|--version" >&2; exit 2 ;;
esac
indent='s/^          \([^ ]\)/                        \1/'
option='^      --[a-z0-9][a-z0-9-]*\( <[^>]*>\)\{0,1\}$'
help=$("$program" --help)
text=$(printf '%s\n' "$help" | sed -e "\\%$option%!$indent")
# The commands: the "  NAME    description" lines of the "Commands:" block.
commands=$(printf '%s\n' "$help" | sed -n '/^Commands:$/,/^$/s/^  \([a-z][a-z0-9-]*\)  .*/\1/p')
name=$(basename "$program")
for command in $commands; do
  part=$("$program" "$command" --help)
  part=$(printf '%s\n' "$part" | sed -e "\\%$option%!$indent" -e "s/^Options:\$/Options of $name $command:/")
  text=$(printf '%s\n\n*Command %s*\n\n%s' "$text" "$command" "$part")
done
printf '%s\n' "$text"
