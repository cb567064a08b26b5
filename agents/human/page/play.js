// The play page: shows the human agent's desk (GET /api/play/observation) and answers with a key
// (POST /api/play/action). Long polls, so a new observation shows as soon as it arrives.
'use strict';

let current = null;   // the observation on screen, or null while waiting
let version = -1;
let sending = false;

// The judge's verdict on the person's last episode, in words.
function verdictLine(v) {
  if (v.retried) return 'Episode ' + v.episode + ' was interrupted (' + v.cause + ') and will start again.';
  const how = v.success ? 'Success' : 'Failure: ' + v.cause.replaceAll('_', ' ') + ' (reached: ' + v.stage + ')';
  return 'Episode ' + v.episode + ': ' + how + ' · IP ' + v.ip.toFixed(0) + ' · ' + v.steps + ' step(s)' +
    (v.detail ? ' · ' + v.detail : '');
}

function show(desk) {
  version = desk.version;
  const status = document.getElementById('status');
  const task = document.getElementById('task');
  const box = document.getElementById('observation');
  const verdict = document.getElementById('verdict');
  const s = desk.score;
  document.getElementById('progress').textContent = desk.episodes_done + ' episode(s) finished' +
    (s && s.scored > 0 ? ' · ' + s.successes + ' of ' + s.scored + ' succeeded (SR ' + s.sr.toFixed(0) +
      ' %, 95 % interval ' + s.sr_ci[0].toFixed(0) + '–' + s.sr_ci[1].toFixed(0) + ' %; mean IP ' + s.ip.toFixed(0) + ')' : '');
  const v = desk.last_verdict;
  verdict.textContent = v ? verdictLine(v) : '';
  verdict.className = v ? (v.success ? 'success' : 'failure') : '';
  verdict.dataset.episode = v ? v.episode : '';
  if (desk.waiting) {
    current = null;
    status.textContent = desk.episodes_done > 0
      ? 'Episode finished. The next one shows here when there is one; once every episode is played, ' +
        'this page keeps your score until you stop mtg play (Ctrl-C where it runs).'
      : 'Waiting for the first episode…';
    task.textContent = '';
    box.replaceChildren();
    return;
  }
  current = desk;
  // A retried episode (infrastructure trouble) starts again from the first step.
  status.replaceChildren(el('b', {}, 'Episode ' + desk.episode), desk.attempt > 0 ? ' (attempt ' + (desk.attempt + 1) +
    ', started again)' : '', ' · step ' + (desk.step + 1) + ' of at most ' + desk.step_limit);
  status.dataset.episode = desk.episode + '/' + desk.attempt;
  status.dataset.step = desk.step;
  task.textContent = desk.task_text;
  box.replaceChildren(renderObservation(desk, {onKey: act}));
  document.getElementById('key').focus();
}

async function act(key) {
  if (!current || sending) return;
  const err = document.getElementById('keyerror');
  if (!current.actions.some((a) => a.key === key)) {
    err.textContent = '"' + key + '" is not offered';
    return;
  }
  err.textContent = '';
  sending = true;
  // Until the next observation shows, this one cannot be answered twice.
  for (const b of document.querySelectorAll('.actions button')) b.disabled = true;
  document.getElementById('status').textContent = 'Sent ' + key + '…';
  try {
    const res = await fetch('/api/play/action', {method: 'POST', headers: {'Content-Type': 'application/json'},
                                                  body: JSON.stringify({key})});
    const body = await res.json();
    if (!res.ok) err.textContent = body.error;
    else if (body.version >= version) show(body);
  } catch (e) {
    ended();
  } finally {
    sending = false;
  }
}

function ended() {
  current = null;
  document.getElementById('status').textContent =
    'The run has ended (or the agent stopped). The results are in the run folder; `mtg view <run>` shows them.';
  document.getElementById('observation').replaceChildren();
}

async function poll() {
  for (;;) {
    try {
      const res = await fetch('/api/play/observation' + (version >= 0 ? '?after=' + version : ''));
      const desk = await res.json();
      // Only a newer desk: the desk's version only grows, and a poll answered just before the
      // person's last click can arrive after the click's own answer (a loaded machine); shown, it
      // put the step already played back on the page with the verdict before (CI, stop 61).
      if (!sending && desk.version > version) show(desk);
    } catch (e) {
      ended();
      return;
    }
  }
}

document.getElementById('keyform').addEventListener('submit', (ev) => {
  ev.preventDefault();
  const input = document.getElementById('key');
  act(input.value.trim());
  input.value = '';
});
poll();
