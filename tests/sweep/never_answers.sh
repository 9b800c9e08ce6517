#!/bin/bash
# A controller that never attaches (the sweep tests' hanging variant): whatever its arguments,
# it sleeps, as a process named ohrp_never_answers (so a test can tell it is gone); sim_host
# waits for it (30 s) past the sweep's time limit.
exec -a ohrp_never_answers sleep 600
