"""``navverse serve``: the benchmark's evaluation server.

A benchmark keeps a test split whose goals only the server knows (its private file, :mod:`navverse.dataset`'s
private splits), takes trajectory submissions over HTTP from teams holding a token, scores them with the
evaluator's own code in worker processes, and shows a leaderboard. One module per job:

- :mod:`.settings`: the server's settings (lease, heartbeat, workers, rate, body cap);
- :mod:`.errors`: :class:`~.errors.ServeError` (a user's mistake at the command line) and
  :class:`~.errors.RefusedError` (a request refused, with its HTTP status);
- :mod:`.db`: the SQLite database (WAL mode) and its migrations;
- :mod:`.teams`: team names and tokens (only their SHA-256 is stored);
- :mod:`.store`: the submission files: an upload streamed to a temporary file within the body cap,
  fsynced and renamed into place;
- :mod:`.benchmark`: the dataset as the server holds it: per split its episode ids, bounds and scenes;
- :mod:`.intake`: an upload checked against its split (the evaluator's reader), refused at any problem;
- :mod:`.queue`: the submissions table: insertion within the team's rate, claims under a lease,
  heartbeats, and the one conditioned finish that records a scoring;
- :mod:`.scoring`: what a worker process runs: the evaluator's scoring, reduced to its public group means;
- :mod:`.scheduler`: the thread that claims work, runs it in the process pool and renews its leases;
- :mod:`.leaderboard`: the best public submission per team and track;
- :mod:`.pages`: the HTML pages (escaped, one inline script, no external asset);
- :mod:`.app`: the FastAPI application (its routes);
- :mod:`.server`: the server run: application, scheduler and uvicorn on one socket.

The package imports nothing itself, so that ``navverse serve --help`` loads neither FastAPI nor uvicorn.
"""
