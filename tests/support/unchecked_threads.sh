#!/bin/sh
# Lists the SystemC threads that test sources under DIR start without the completion check, and
# fails if there is one: every test thread starts through rcsim::test::spawn_checked (or
# spawn_forever for a loop that never returns), declared in tests/support/sc_test.h, which itself
# is the one place allowed to call sc_spawn.
# Usage: unchecked_threads.sh DIR
dir=${1:?usage: unchecked_threads.sh DIR}
if grep -rnE --include='*.h' --include='*.cpp' '\b(sc_spawn|SC_THREAD|SC_CTHREAD)\b' "$dir" |
    grep -v "^$dir/support/"; then
    echo "start these with rcsim::test::spawn_checked or spawn_forever (tests/support/sc_test.h)" >&2
    exit 1
fi
exit 0
