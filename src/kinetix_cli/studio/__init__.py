"""The level studio (`kinetix studio`): a local web app to build, check, play and watch agents on levels, running
the project's own parser, environment and agents.

`workspace` keeps every file access inside the studio's folder; `service` does the work (check, generate,
mutate, play, watch, evaluate) on JSON values; `app` is the HTTP layer (token, body limits, errors); `server`
runs it; `static/` is the page (plain HTML, CSS and JavaScript modules, no build step, no network)."""
