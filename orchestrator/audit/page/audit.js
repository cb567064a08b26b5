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
  document.getElementById('progress').textContent = s.rater + ': ' + s.answered + ' of ' + s.total + ' tasks answered';
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

// Observations come one at a time: the picks asked in one are given before the next is shown
// (a later one may show their answers), and the task is judged once all are shown.
function renderForm(item) {
  const form = document.getElementById('answer');
  const a = item.answer || {};
  const picks = item.picks || {};
  const all = item.revealed + 1 >= item.observations_total;
  const questions = item.questions.map(q => el('label', {},
    q.ask + ' (seen in observation ' + (q.observation + 1) + ') ',
    el('input', Object.assign({class: 'pick', name: q.id, 'data-question': q.id,
                 placeholder: q.id.endsWith('.place') ? '5' : 'o3', value: picks[q.id] || ''},
                 q.locked ? {disabled: 'disabled'} : {})),
    ' ', el('span', {class: 'muted'}, q.locked ? 'given' : 'empty: cannot tell')));
  const reasons = el('select', {name: 'reason'}, ...state.summary.reasons.map(r =>
    el('option', Object.assign({value: r}, a.reason === r ? {selected: 'selected'} : {}), r + ': ' + (REASON_WORDS[r] || r))));
  const radio = (value, text) => el('label', {}, el('input', Object.assign({type: 'radio', name: 'valid', value: value},
    (a.valid === true && value === 'yes') || (a.valid === false && value === 'no') ? {checked: 'checked'} : {})), ' ' + text);
  const open = (data) => {
    const out = {};
    for (const q of item.questions) if (!q.locked) out[q.id] = (data.get(q.id) || '').trim().toLowerCase();
    return out;
  };
  const judge = all ? [el('div', {}, 'Could a person do this task from what is shown?'),
    radio('yes', 'yes, the task is valid'), radio('no', 'no, because:'), reasons,
    el('label', {}, 'Note: ', el('input', {name: 'note', size: 60, value: a.note || ''})),
    el('button', {type: 'submit', id: 'save'}, 'Save and go to the next task')]
    : [el('button', {type: 'submit', id: 'reveal'}, 'Give these and show observation ' + (item.revealed + 2) + ' of ' +
                                                    item.observations_total)];
  form.replaceChildren(
    el('div', {class: 'muted'}, 'Which number does each object have? Type its key as shown in the images (e.g. o3); ' +
       'for where the item goes, the key of the free space or part that does what the task says (e.g. 5).'),
    ...questions, ...judge, el('span', {id: 'saved'}), el('div', {id: 'formerror', class: 'error'}));
  form.onsubmit = async (ev) => {
    ev.preventDefault();
    const data = new FormData(form);
    if (!all) {
      const r = await fetch('/api/audit/items/' + item.index + '/reveal',
        {method: 'POST', headers: {'Content-Type': 'application/json'}, body: JSON.stringify({picks: open(data)})});
      const body = await r.json();
      if (!r.ok) { document.getElementById('formerror').textContent = body.error; return; }
      await showItem(item.index);
      return;
    }
    const valid = data.get('valid');
    if (!valid) { document.getElementById('formerror').textContent = 'Say whether the task is valid.'; return; }
    const body = {valid: valid === 'yes', note: data.get('note') || '', picks: open(data)};
    if (valid === 'no') body.reason = data.get('reason');
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
