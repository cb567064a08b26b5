// The audit page: one sampled task at a time, what the agent sees, and the questions. No
// framework: plain DOM (el() and renderObservation() come from observation.js).
'use strict';

const REASON_WORDS = {
  occluded: 'an object it names is hidden or too small to see',
  unclear_noun: 'a noun does not fit what the object looks like',
  unreadable_marks: 'the numbers cannot be told apart or tied to their objects',
  ambiguous_text: 'the text could mean more than one object or place',
  infeasible: 'it cannot be done as asked',
  other: 'something else (say what in the note)',
};

let state = {summary: null, index: null};

async function getJson(url) {
  const r = await fetch(url);
  const body = await r.json();
  if (!r.ok) throw new Error(body.error || r.statusText);
  return body;
}

async function loadSummary() {
  state.summary = await getJson('/api/audit');
  const s = state.summary;
  document.getElementById('progress').textContent = s.answered + ' of ' + s.total + ' tasks answered';
  const list = document.getElementById('tasks');
  list.replaceChildren(...s.items.map(it => el('a', {
    href: '#' + it.index, 'data-index': it.index,
    class: (it.answered ? 'answered' : '') + (it.index === state.index ? ' current' : ''),
    title: it.task_id}, 'L' + it.level + ' #' + it.index)));
}

function firstUnanswered() {
  const it = state.summary.items.find(i => !i.answered);
  return it ? it.index : (state.summary.items.length ? state.summary.items[0].index : null);
}

async function showItem(index) {
  state.index = index;
  await loadSummary();
  const item = await getJson('/api/audit/items/' + index);
  document.getElementById('status').textContent = 'Task ' + (index + 1) + ' of ' + state.summary.total +
    ' (level ' + item.level + ')';
  document.getElementById('task').replaceChildren(el('b', {}, 'Task: '), item.task_text);
  const obs = document.getElementById('observations');
  obs.replaceChildren(...item.observations.map((o, k) => el('section', {'data-observation': k},
    el('div', {class: 'obs-title'}, (k + 1) + '. ' + o.title), renderObservation(o, {eager: true}))));
  renderForm(item);
}

function renderForm(item) {
  const form = document.getElementById('answer');
  const a = item.answer || {};
  const picks = a.picks || {};
  const questions = item.questions.map(q => el('label', {},
    q.ask + ' (seen in observation ' + (q.observation + 1) + ') ',
    el('input', {class: 'pick', name: q.id, 'data-question': q.id, placeholder: 'o3', value: picks[q.id] || ''}),
    ' ', el('span', {class: 'muted'}, 'empty: cannot tell')));
  const reasons = el('select', {name: 'reason'}, ...state.summary.reasons.map(r =>
    el('option', Object.assign({value: r}, a.reason === r ? {selected: 'selected'} : {}), r + ': ' + (REASON_WORDS[r] || r))));
  const radio = (value, text) => el('label', {}, el('input', Object.assign({type: 'radio', name: 'valid', value: value},
    (a.valid === true && value === 'yes') || (a.valid === false && value === 'no') ? {checked: 'checked'} : {})), ' ' + text);
  form.replaceChildren(
    el('div', {class: 'muted'}, 'Which number does each object have? Type its key as shown in the images (e.g. o3).'),
    ...questions,
    el('div', {}, 'Could a person do this task from what is shown?'),
    radio('yes', 'yes, the task is valid'), radio('no', 'no, because:'), reasons,
    el('label', {}, 'Note: ', el('input', {name: 'note', size: 60, value: a.note || ''})),
    el('button', {type: 'submit', id: 'save'}, 'Save and go to the next task'), el('span', {id: 'saved'}),
    el('div', {id: 'formerror', class: 'error'}));
  form.onsubmit = async (ev) => {
    ev.preventDefault();
    const data = new FormData(form);
    const valid = data.get('valid');
    if (!valid) { document.getElementById('formerror').textContent = 'Say whether the task is valid.'; return; }
    const body = {valid: valid === 'yes', note: data.get('note') || '', picks: {}};
    if (valid === 'no') body.reason = data.get('reason');
    for (const q of item.questions) body.picks[q.id] = (data.get(q.id) || '').trim().toLowerCase();
    const r = await fetch('/api/audit/items/' + item.index + '/answer',
      {method: 'POST', headers: {'Content-Type': 'application/json'}, body: JSON.stringify(body)});
    const answer = await r.json();
    if (!r.ok) { document.getElementById('formerror').textContent = answer.error; return; }
    document.getElementById('saved').textContent = 'saved';
    const next = answer.next === null ? item.index : answer.next;
    location.hash = '#' + next;
    if (next === item.index) await showItem(next);
  };
}

async function route() {
  try {
    if (!state.summary) await loadSummary();
    const wanted = parseInt(location.hash.slice(1), 10);
    await showItem(Number.isNaN(wanted) ? firstUnanswered() : wanted);
  } catch (e) {
    document.getElementById('status').textContent = 'Error: ' + e.message;
  }
}

window.addEventListener('hashchange', route);
route();
