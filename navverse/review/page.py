"""The review page (:data:`PAGE`): one self-contained HTML document, inline CSS and plain JavaScript.

It fetches ``/api/episodes`` from the server that served it, and nothing from anywhere else. Text from
the dataset is put in place with ``textContent``, never as HTML. Elements the tests drive: a card is
``article.card[data-episode=<id>]`` with ``data-decision``, its ``input.reason``, its
``button[data-action=accept|reject]`` and its ``.status``; ``body[data-ready]`` is set once the list is
drawn.
"""

from __future__ import annotations

__all__ = ["PAGE", "PAGE_SIZE"]

PAGE_SIZE = 25
"""Episodes per page of the list."""

_STYLE = """
body { font: 14px/1.4 system-ui, sans-serif; margin: 0; background: #f4f4f2; color: #222; }
header { position: sticky; top: 0; background: #fff; border-bottom: 1px solid #ccc; padding: 8px 16px;
  z-index: 1; }
h1 { font-size: 18px; margin: 0 0 6px; }
.controls { display: flex; gap: 12px; align-items: center; flex-wrap: wrap; }
main { padding: 12px 16px; }
.card { background: #fff; border: 1px solid #ccc; border-left: 6px solid #bbb; border-radius: 4px;
  margin: 0 0 12px; padding: 8px 12px; }
.card[data-decision=accept] { border-left-color: #2a9d3a; }
.card[data-decision=reject] { border-left-color: #c62828; }
.head { display: flex; gap: 12px; flex-wrap: wrap; align-items: baseline; }
.head .id { font-weight: 600; font-family: ui-monospace, monospace; }
.head .meta { color: #555; }
.pics { display: flex; gap: 8px; flex-wrap: wrap; align-items: flex-start; margin: 6px 0; }
.pics img.bev { width: 480px; height: auto; min-height: 200px; background: #eee; }
.frames { display: grid; grid-template-columns: repeat(2, 240px); gap: 4px; }
.frames img { width: 240px; height: 180px; background: #ddd; }
ul.instructions { margin: 4px 0; padding-left: 18px; }
ul.instructions .type { display: inline-block; min-width: 70px; color: #666; font-size: 12px; }
.decide { display: flex; gap: 8px; align-items: center; margin-top: 6px; }
.decide input.reason { flex: 1; max-width: 520px; padding: 4px 6px; }
.decide button { padding: 4px 14px; cursor: pointer; }
button[data-action=accept] { background: #e5f4e7; border: 1px solid #2a9d3a; }
button[data-action=reject] { background: #fbe6e6; border: 1px solid #c62828; }
.status { color: #444; }
.status.error { color: #c62828; font-weight: 600; }
#error { color: #c62828; font-weight: 600; }
"""

_SCRIPT = """
"use strict";
const PAGE_SIZE = __PAGE_SIZE__;
const view = { episodes: [], page: 0 };

function el(tag, attrs, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attrs || {})) {
    if (key === "text") node.textContent = value;
    else node.setAttribute(key, value);
  }
  for (const child of children) if (child) node.appendChild(child);
  return node;
}

function choose(id, values) {
  const select = document.getElementById(id);
  for (const value of values) select.appendChild(el("option", { text: value }));
  select.addEventListener("change", () => { view.page = 0; render(); });
}

function shown() {
  const split = document.getElementById("split").value;
  const task = document.getElementById("task").value;
  const state = document.getElementById("state").value;
  return view.episodes.filter((e) =>
    (!split || e.split === split) && (!task || e.task === task) &&
    (!state || (state === "undecided" ? !e.decision : e.decision && e.decision.decision === state)));
}

function statusText(decision) {
  if (!decision) return "undecided";
  const word = decision.decision === "reject" ? "rejected" : "accepted";
  return word + (decision.reason ? ": " + decision.reason : "") + " (" + decision.at + ")";
}

function summary() {
  const rejected = view.episodes.filter((e) => e.decision && e.decision.decision === "reject").length;
  const accepted = view.episodes.filter((e) => e.decision && e.decision.decision === "accept").length;
  document.getElementById("summary").textContent =
    view.episodes.length + " episodes: " + accepted + " accepted, " + rejected + " rejected, " +
    (view.episodes.length - accepted - rejected) + " undecided";
}

async function decide(episode, decision, card) {
  const reason = card.querySelector("input.reason").value;
  const status = card.querySelector(".status");
  status.className = "status";
  status.textContent = "saving…";
  try {
    const response = await fetch("/api/decision", {
      method: "POST",
      headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ episode_id: episode.id, decision: decision, reason: reason }),
    });
    const answer = await response.json();
    if (!response.ok) throw new Error(answer.error || response.statusText);
    episode.decision = { decision: answer.decision, reason: answer.reason, at: answer.at };
    card.dataset.decision = answer.decision;
    status.textContent = statusText(episode.decision);
    summary();
  } catch (error) {
    status.className = "status error";
    status.textContent = "not saved: " + error.message;
  }
}

function card(episode) {
  const id = encodeURIComponent(episode.id);
  const frames = el("div", { class: "frames" });
  for (let k = 0; k < 4; k++) {
    frames.appendChild(el("img", { src: "/keyframes/" + id + "/" + k + ".png", loading: "lazy",
                                   alt: "keyframe " + (k + 1) + " of 4" }));
  }
  const instructions = el("ul", { class: "instructions" });
  for (const item of episode.instructions) {
    instructions.appendChild(el("li", {}, el("span", { class: "type", text: item.type }),
                                document.createTextNode(" " + item.text)));
  }
  if (!episode.instructions.length) {
    instructions.appendChild(el("li", {}, el("span", { class: "type", text: "goal" }),
                                document.createTextNode(" find a " + episode.category)));
  }
  const meta = [episode.split, episode.task, episode.scene + " (" + episode.scene_type + ")",
                episode.category, episode.geodesic.toFixed(1) + " m", episode.difficulty || "-"];
  const node = el("article", { class: "card", "data-episode": episode.id,
                               "data-decision": episode.decision ? episode.decision.decision : "" },
    el("div", { class: "head" }, el("span", { class: "id", text: episode.id }),
       el("span", { class: "meta", text: meta.join(" · ") })),
    el("div", { class: "pics" },
       el("a", { href: "/bev/" + id + ".png", target: "_blank", title: "full size" },
          el("img", { class: "bev", src: "/bev/" + id + ".png", loading: "lazy", alt: "bird's-eye view" })),
       frames),
    instructions,
    el("div", { class: "decide" },
       el("input", { class: "reason", type: "text", maxlength: "2000",
                     placeholder: "reason (required to reject)" }),
       el("button", { "data-action": "accept", text: "Accept" }),
       el("button", { "data-action": "reject", text: "Reject" }),
       el("span", { class: "status", text: statusText(episode.decision) })));
  if (episode.decision) node.querySelector("input.reason").value = episode.decision.reason;
  for (const button of node.querySelectorAll("button[data-action]")) {
    button.addEventListener("click", () => decide(episode, button.dataset.action, node));
  }
  return node;
}

function render() {
  const episodes = shown();
  const pages = Math.max(1, Math.ceil(episodes.length / PAGE_SIZE));
  view.page = Math.min(Math.max(view.page, 0), pages - 1);
  const list = document.getElementById("list");
  list.replaceChildren(...episodes.slice(view.page * PAGE_SIZE, (view.page + 1) * PAGE_SIZE).map(card));
  document.getElementById("page").textContent =
    "page " + (view.page + 1) + " of " + pages + " (" + episodes.length + " shown)";
  summary();
  window.scrollTo(0, 0);
}

async function load() {
  const response = await fetch("/api/episodes");
  if (!response.ok) throw new Error("the episode list did not load (" + response.status + ")");
  const data = await response.json();
  view.episodes = data.episodes;
  document.title = "Review: " + data.dataset + " v" + data.version;
  document.getElementById("title").textContent =
    "Review: " + data.dataset + " v" + data.version + " (" + data.embodiment + ") → " + data.decisions_file;
  choose("split", data.splits);
  choose("task", data.tasks);
  document.getElementById("state").addEventListener("change", () => { view.page = 0; render(); });
  document.getElementById("prev").addEventListener("click", () => { view.page--; render(); });
  document.getElementById("next").addEventListener("click", () => { view.page++; render(); });
  render();
  document.body.dataset.ready = "1";
}

load().catch((error) => { document.getElementById("error").textContent = error.message; });
""".replace("__PAGE_SIZE__", str(PAGE_SIZE))

PAGE = f"""<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>Review</title>
<style>{_STYLE}</style>
</head>
<body>
<header>
<h1 id="title">Review</h1>
<div class="controls">
<label>split <select id="split"><option value="">all</option></select></label>
<label>task <select id="task"><option value="">all</option></select></label>
<label>decision <select id="state"><option value="">all</option><option value="undecided">undecided</option>
<option value="accept">accepted</option><option value="reject">rejected</option></select></label>
<button id="prev" type="button">previous</button><span id="page"></span>
<button id="next" type="button">next</button>
<span id="summary"></span><span id="error"></span>
</div>
</header>
<main id="list"></main>
<script>{_SCRIPT}</script>
</body>
</html>
"""
"""The review page."""
