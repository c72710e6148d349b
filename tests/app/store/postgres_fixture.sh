#!/usr/bin/env bash
# A private PostgreSQL server for the store's tests (tests/app/store), from Debian's `postgresql`
# package: a cluster made with initdb in a temporary folder, listening on a unix socket in that
# folder (the superuser, trust) and on 127.0.0.1 at a free port (the stations' role, with a
# password: scram-sha-256, so that wrong credentials can be tested). PostgreSQL refuses to run as
# root: as root the server runs as the `postgres` user.
#
#   postgres_fixture.sh start STATE     start it; STATE (a file) then holds how to reach it, or
#                                       SKIP=why when the server's binaries are not installed
#   postgres_fixture.sh crash STATE     pg_ctl stop -m immediate (every process quits at once,
#                                       no checkpoint: recovery on the next start)
#   postgres_fixture.sh restart STATE   start it again on the same port
#   postgres_fixture.sh stop STATE      stop it and remove its folder and STATE
#
# ctest runs start and stop as the fixture `store_postgres` (tests/app/store/CMakeLists.txt).
# fsync and full_page_writes are off (a test server's data need not survive a power cut; its
# databases are made and dropped in milliseconds so).
set -u

# The server outlives this script: it must not inherit any descriptor its caller holds open (a
# `flock` lock taken around ctest would otherwise be held by the server until it stops).
for fd_path in /proc/$$/fd/*; do
  fd=${fd_path##*/}
  if [ "$fd" -gt 2 ] 2>/dev/null; then eval "exec $fd>&-" 2>/dev/null; fi
done

cmd=${1:-}
state=${2:-}
if [ -z "$cmd" ] || [ -z "$state" ]; then
  echo "usage: $0 start|crash|restart|stop STATE_FILE" >&2
  exit 64
fi
script=$(readlink -f "$0")

value() { sed -n "s/^$1=//p" "$state" 2>/dev/null | head -n 1; }

as_server() {
  if [ "$(id -u)" -eq 0 ]; then runuser -u postgres -- "$@"; else "$@"; fi
}

server_options() {
  # fsync off: the OS keeps what was written if only the server's processes die (the crash
  # test); synchronous_commit stays on, or a commit could be lost with them.
  echo "-k $1 -p $2 -c listen_addresses=127.0.0.1 -c fsync=off -c full_page_writes=off" \
       "-c max_connections=40"
}

stop_server() {
  local dir bin
  dir=$(value PG_DIR)
  bin=$(value PG_BIN)
  if [ -n "$dir" ] && [ -d "$dir/data" ]; then
    as_server "$bin/pg_ctl" -D "$dir/data" -m fast -w stop >/dev/null 2>&1 ||
      as_server "$bin/pg_ctl" -D "$dir/data" -m immediate -w stop >/dev/null 2>&1
  fi
  if [ -n "$dir" ] && [ -d "$dir" ]; then rm -rf "$dir"; fi
}

skip() {
  echo "SKIP=$1" > "$state"
  echo "postgres_fixture: the PostgreSQL half of the store's tests will skip: $1"
  exit 0
}

case "$cmd" in
  start)
    if [ -f "$state" ]; then stop_server; fi  # a run that stopped half-way left one behind
    rm -f "$state"
    mkdir -p "$(dirname "$state")"
    bin=""
    for d in $(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V -r); do
      if [ -x "$d/initdb" ] && [ -x "$d/pg_ctl" ] && [ -x "$d/postgres" ]; then bin=$d; break; fi
    done
    if [ -z "$bin" ]; then
      skip "PostgreSQL's server is not installed (no /usr/lib/postgresql/*/bin/initdb): apt-get install postgresql (packaging/install-deps.sh installs it)"
    fi
    if [ "$(id -u)" -eq 0 ] && ! id -u postgres >/dev/null 2>&1; then
      skip "running as root, but there is no 'postgres' user to run the server as (PostgreSQL refuses root)"
    fi
    dir=$(mktemp -d /tmp/lap-pg.XXXXXX)
    if [ "$(id -u)" -eq 0 ]; then chown postgres: "$dir"; fi
    if ! as_server "$bin/initdb" -D "$dir/data" -U postgres --auth-local=trust \
         --auth-host=scram-sha-256 --no-sync -E UTF8 --locale=C.UTF-8 >"$dir/initdb.log" 2>&1; then
      echo "postgres_fixture: initdb failed:" >&2
      cat "$dir/initdb.log" >&2
      rm -rf "$dir"
      exit 1
    fi
    # A free port: try a few at random (a port in use makes the start fail at once).
    port=""
    for _ in $(seq 1 20); do
      candidate=$((20000 + RANDOM % 30000))
      if as_server "$bin/pg_ctl" -D "$dir/data" -l "$dir/server.log" -w -t 30 \
           -o "$(server_options "$dir" "$candidate")" start >/dev/null 2>&1; then
        port=$candidate
        break
      fi
    done
    if [ -z "$port" ]; then
      echo "postgres_fixture: the server did not start:" >&2
      tail -n 20 "$dir/server.log" >&2
      rm -rf "$dir"
      exit 1
    fi
    password="station-test-$(od -An -N8 -tx1 /dev/urandom | tr -d ' \n')"
    if ! as_server "$bin/psql" -h "$dir" -p "$port" -U postgres -d postgres -v ON_ERROR_STOP=1 \
         -q -c "CREATE ROLE station LOGIN PASSWORD '$password'" >"$dir/psql.log" 2>&1; then
      echo "postgres_fixture: cannot create the stations' role:" >&2
      cat "$dir/psql.log" >&2
      as_server "$bin/pg_ctl" -D "$dir/data" -m immediate -w stop >/dev/null 2>&1
      rm -rf "$dir"
      exit 1
    fi
    {
      echo "PG_BIN=$bin"
      echo "PG_DIR=$dir"
      echo "PG_SOCKET=$dir"
      echo "PG_PORT=$port"
      echo "PG_SUPERUSER=postgres"
      echo "PG_USER=station"
      echo "PG_PASSWORD=$password"
      echo "PG_SCRIPT=$script"
    } > "$state"
    chmod 600 "$state"
    echo "postgres_fixture: PostgreSQL ($("$bin/postgres" --version)) in $dir on port $port"
    ;;
  crash)
    [ -f "$state" ] || exit 1
    as_server "$(value PG_BIN)/pg_ctl" -D "$(value PG_DIR)/data" -m immediate -w stop >/dev/null
    ;;
  restart)
    [ -f "$state" ] || exit 1
    dir=$(value PG_DIR)
    as_server "$(value PG_BIN)/pg_ctl" -D "$dir/data" -l "$dir/server.log" -w -t 30 \
      -o "$(server_options "$dir" "$(value PG_PORT)")" start >/dev/null
    ;;
  stop)
    if [ -f "$state" ]; then stop_server; rm -f "$state"; fi
    ;;
  *)
    echo "usage: $0 start|crash|restart|stop STATE_FILE" >&2
    exit 64
    ;;
esac
