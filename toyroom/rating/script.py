"""The rating page's script (plain JavaScript, no build step): the consent screen, the replay
drawn on a canvas, the sliders, and the answer sent to the server.

The page reads ``window.RATING`` (written by :mod:`.page`). ``window.replayDone`` is a
promise that settles once the replay has reached the question's last tick (the answer
button is enabled then); a test waits on it. ``I agree`` records the consent on the server
before the question is shown (the server takes no answer without it); a page whose
participant the server knows to have agreed skips the consent. After an answer is saved the
page reloads and the server gives it the next unanswered question, so a reload always
resumes there; an answer the server refuses as out of turn (409: answered already, no
consent, another question shown) reloads too; one it could not save (a full disk: 507) says
"Not saved" with the server's reason, and Next may be pressed again.
"""

SCRIPT = r"""
"use strict";
const S = window.RATING;
const $ = (id) => document.getElementById(id);
let finishReplay;
window.replayDone = new Promise((resolve) => { finishReplay = resolve; });

function layout(canvas, plan) {
  const pad = 12;
  const s = Math.min((canvas.width - 2 * pad) / plan.columns, (canvas.height - 2 * pad) / plan.rows);
  const ox = (canvas.width - s * plan.columns) / 2, oy = (canvas.height - s * plan.rows) / 2;
  return { s, x: (c) => ox + c * s, y: (r) => oy + (plan.rows - r) * s };
}

function label(ctx, text, x, y, font, ink, back) {
  ctx.font = font;
  const w = ctx.measureText(text).width, h = parseInt(font.match(/(\d+)px/)[1], 10);
  if (back) {
    ctx.fillStyle = back;
    ctx.fillRect(x - w / 2 - 3, y - h / 2 - 2, w + 6, h + 4);
  }
  ctx.fillStyle = ink;
  ctx.textAlign = "center";
  ctx.textBaseline = "middle";
  ctx.fillText(text, x, y);
}

function drawPlan(ctx, plan, L) {
  const owner = new Map();
  plan.rooms.forEach((room) => room.cells.forEach(([c, r]) => owner.set(c + "," + r, room.id)));
  const doors = new Set(plan.doors.map(([c, r]) => c + "," + r));
  ctx.fillStyle = "#ffffff";
  ctx.fillRect(0, 0, ctx.canvas.width, ctx.canvas.height);
  plan.rooms.forEach((room) => {
    ctx.fillStyle = room.colour;
    room.cells.forEach(([c, r]) => ctx.fillRect(L.x(c), L.y(r + 1), L.s + 0.5, L.s + 0.5));
  });
  ctx.fillStyle = "#fafafa";
  plan.doors.forEach(([c, r]) => ctx.fillRect(L.x(c), L.y(r + 1), L.s, L.s));
  ctx.strokeStyle = "#7a7a7a";
  ctx.lineWidth = 3;
  ctx.beginPath();
  const sides = [[1, 0, 1, 0, 1, 1], [-1, 0, 0, 0, 0, 1], [0, 1, 0, 1, 1, 1], [0, -1, 0, 0, 1, 0]];
  plan.rooms.forEach((room) => room.cells.forEach(([c, r]) => sides.forEach(([dc, dr, a, b, e, f]) => {
    const key = (c + dc) + "," + (r + dr);
    if (owner.get(key) === room.id || doors.has(key)) return;
    ctx.moveTo(L.x(c + a), L.y(r + b));
    ctx.lineTo(L.x(c + e), L.y(r + f));
  })));
  ctx.stroke();
  plan.spots.forEach((spot) => {
    const [c, r] = spot.cell;
    ctx.fillStyle = spot.play ? "#3c9a64" : "#8a8a8a";
    ctx.fillRect(L.x(c + 0.3), L.y(r + 0.7), L.s * 0.4, L.s * 0.4);
    label(ctx, spot.id, L.x(c + 0.5), L.y(r + 0.12), "bold 13px sans-serif", "#222222", "#ffffff");
  });
  plan.rooms.forEach((room) => {
    const cs = room.cells.map(([c]) => c), rs = room.cells.map(([, r]) => r);
    const cx = (Math.min(...cs) + Math.max(...cs) + 1) / 2, bottom = Math.min(...rs);
    label(ctx, room.name, L.x(cx), L.y(bottom) - 14, "bold 17px sans-serif", "#222222", null);
  });
}

function drawFrame(ctx, plan, L, frame) {
  drawPlan(ctx, plan, L);
  frame.items.forEach((item, n) => {
    if (!item) return;
    const x = L.x(item.at[0]) + (item.held ? L.s * 0.25 : 0), y = L.y(item.at[1]);
    ctx.fillStyle = plan.items[n].colour;
    ctx.beginPath();
    ctx.arc(x, y, Math.max(5, L.s * 0.14), 0, 2 * Math.PI);
    ctx.fill();
    label(ctx, plan.items[n].label, x, y + Math.max(13, L.s * 0.3), "12px sans-serif", "#222222", "#ffffff");
  });
  frame.agents.forEach((at, n) => {
    if (!at) return;
    const agent = plan.agents[n], x = L.x(at[0]), y = L.y(at[1]);
    const size = Math.max(8, agent.radius * L.s);
    ctx.fillStyle = agent.colour;
    if (agent.person) {
      ctx.beginPath();
      ctx.arc(x, y, size, 0, 2 * Math.PI);
      ctx.fill();
      if (agent.id === S.question.person) {
        ctx.strokeStyle = "#000000";
        ctx.lineWidth = 2;
        ctx.stroke();
      }
    } else {
      ctx.fillRect(x - size, y - size, 2 * size, 2 * size);
    }
    const below = agent.person ? -1 : 1;
    label(ctx, agent.id, x, y + below * (size + 12), "bold 16px sans-serif", "#111111", "#ffffff");
  });
  const seconds = (frame.tick * S.tickSeconds).toFixed(1);
  $("tick").textContent = `tick ${frame.tick} (${seconds} s); replay at ${S.rate}x real time`;
  const said = S.captions.filter((c) => c.tick <= frame.tick).slice(-3);
  $("said").replaceChildren(...said.map((c) => {
    const line = document.createElement("div");
    line.textContent = c.text;
    return line;
  }));
}

function replay() {
  const canvas = $("map"), ctx = canvas.getContext("2d"), plan = S.plan, frames = S.frames;
  const L = layout(canvas, plan);
  const msPerTick = (1000 * S.tickSeconds) / S.rate;  // the stated rate, whatever the clip's length
  let n = 0;
  $("submit").disabled = true;
  clearTimeout(window.replayTimer);
  function step() {
    drawFrame(ctx, plan, L, frames[n]);
    if (n < frames.length - 1) {
      const wait = (frames[n + 1].tick - frames[n].tick) * msPerTick;
      n += 1;
      window.replayTimer = setTimeout(step, wait);
    } else {
      $("submit").disabled = false;
      finishReplay(frames[n].tick);
    }
  }
  step();
}

function sliders() {
  const box = $("sliders");
  S.question.targets.forEach((target, n) => {
    const row = document.createElement("label");
    row.className = "slider";
    row.innerHTML = '<span class="name"></span><input type="range" min="0" max="100" value="50">' +
      '<output>50</output>';
    row.querySelector(".name").textContent = S.question.labels[n];
    const input = row.querySelector("input");
    input.dataset.target = target;
    input.addEventListener("input", () => {
      row.querySelector("output").textContent = input.value;
      input.dataset.touched = "yes";  // an untouched slider is no answer (issue 55)
    });
    box.appendChild(row);
  });
}

async function submit() {
  const untouched = [...document.querySelectorAll("#sliders input")].filter((i) => !i.dataset.touched);
  if (untouched.length) {
    $("status").textContent = "Move every slider before going on (leave it where it is by moving it back).";
    return;
  }
  $("submit").disabled = true;
  const values = {};
  document.querySelectorAll("#sliders input").forEach((input) => {
    values[input.dataset.target] = Number(input.value) / 100;
  });
  const said = await send(S.answerUrl, { question: S.question.id, values });
  if (said.ok || said.status === 409) {
    location.reload();
  } else {
    $("status").textContent = "Not saved: " + said.text;
    $("submit").disabled = false;
  }
}

async function send(url, body) {
  try {
    const response = await fetch(url, {
      method: "POST",
      headers: { "Content-Type": "application/json" },
      body: JSON.stringify(body),
    });
    return { ok: response.ok, status: response.status, text: await response.text() };
  } catch (err) {
    return { ok: false, status: 0, text: "the server did not answer (" + err.message + "); try again" };
  }
}

async function agree() {
  $("agree").disabled = true;
  const said = await send(S.consentUrl, { consent: true });
  if (said.ok) {
    start();
  } else {
    $("agreeStatus").textContent = "Not recorded: " + said.text;
    $("agree").disabled = false;
  }
}

function start() {
  $("consent").hidden = true;
  $("prompt").textContent = S.question.text;
  $("task").hidden = false;
  sliders();
  replay();
}

if (!S.question) {
  $("done").hidden = false;
  finishReplay(null);
} else {
  $("agree").addEventListener("click", agree);
  $("again").addEventListener("click", replay);
  $("submit").addEventListener("click", submit);
  if (S.consented) start(); else $("consent").hidden = false;
}
"""
