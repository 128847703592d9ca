"""Hypothesis's example database for a campaign (``ptpcert fuzz --database``): none, a
directory (on a disk several machines may share) or a Redis server."""

from __future__ import annotations

from hypothesis.database import DirectoryBasedExampleDatabase

from ptpcert.results import directory_problem

#: how long a Redis server may take to accept the connection (seconds)
REDIS_CONNECT_S = 10.0


def open_database(spec: str | None):
    """Hypothesis's example database for ``--database``: None for none; ``redis://HOST:PORT/DB``
    (also ``rediss://``, ``unix://``) for a Redis server, through hypothesis's
    ``RedisExampleDatabase`` (the ``hypothesis[redis]`` extra); otherwise a directory, which
    may be on a disk that several machines share. Every process and machine that opens the
    same database shares the campaign: failing examples saved by one are replayed (and
    shrunk further) by the others. A Redis server that does not answer, or a directory
    where nothing can be written, is a ValueError saying so."""
    if not spec:
        return None
    if spec.startswith(("redis://", "rediss://", "unix://")):
        try:
            import redis
            from hypothesis.extra.redis import RedisExampleDatabase
        except ImportError:
            raise ValueError(f"database {spec}: a Redis database needs the hypothesis[redis] extra "
                             "(pip install 'hypothesis[redis]')") from None
        client = redis.Redis.from_url(spec, socket_connect_timeout=REDIS_CONNECT_S)
        try:   # before the first example: a campaign whose every round fails to reach its
            client.ping()   # database would end with "0 findings" as if it had searched
        except redis.exceptions.RedisError as exc:
            client.close()
            raise ValueError(f"database {spec}: the Redis server does not answer "
                             f"({' '.join(str(exc).split())[:200]})") from None
        return RedisExampleDatabase(client)
    problem = directory_problem(spec)
    if problem:
        raise ValueError(f"database {spec}: {problem}")
    return DirectoryBasedExampleDatabase(spec)
