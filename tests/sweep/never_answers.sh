#!/bin/sh
# A controller that never attaches (the sweep tests' hanging variant): whatever its arguments,
# it sleeps; sim_host waits for it (30 s) past the sweep's time limit.
exec sleep 600
