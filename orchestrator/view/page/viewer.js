// The viewer's single page: a hash router over the JSON API of `mtg view` (docs/view.md).
//   #/                                runs
//   #/run/<run>                       overview: Table 3, paper rows, Sankey (click a flow), causes
//   #/run/<run>/episodes?<filters>    episode list
//   #/run/<run>/episode/<id>[/step/<k>][?attempt=k]  every step of one episode (scrolled to step k)
//   #/compare?a=<run>/<id>&b=<run>/<id>   two episodes side by side
//   #/comparison?a=<run>[&b=<run>][&baseline=<agent>]  paired comparison (mtg compare)
'use strict';

const main = document.getElementById('main');
let refreshTimer = null;

// Only the newest route may draw. A page left while its answers were still coming (a second hash
// change during a slow list) would otherwise replace the page the reader went to when they came.
let routeSeq = 0;
class StaleRoute extends Error {}

// Replaces the page's content (skipping absent parts) and notes when it was drawn and which hash it
// shows: tests and the first-paint figure read window.mtgRendered and window.mtgShown.
function show(...parts) {
  main.replaceChildren(...parts.filter((p) => p !== null && p !== undefined));
  for (const f of main.querySelectorAll('input, select, textarea')) f.dataset.shown = f.value;
  window.mtgRendered = performance.now();
  window.mtgShown = location.hash;
}

async function fetchApi(path) {
  // An exported site (mtg export) answers from its data files: static_api.js.
  if (window.mtgStaticApi) return window.mtgStaticApi(path);
  const res = await fetch(path);
  const body = res.headers.get('Content-Type').startsWith('application/json') ? await res.json() : await res.text();
  if (!res.ok) throw new Error(body.error || res.statusText);
  return body;
}

// An answer that arrives after the reader moved on ends the route that asked for it.
async function api(path) {
  const seq = routeSeq;
  const body = await fetchApi(path);
  if (seq !== routeSeq) throw new StaleRoute(path);
  return body;
}

function unlessStale(err) {
  if (!(err instanceof StaleRoute)) throw err;
}

const ciText = (ci) => (ci ? '[' + fmt(ci[0]) + ', ' + fmt(ci[1]) + ']' : '');
const fmt = (v) => (v === null || v === undefined ? '–' : (Math.round(v * 10) / 10).toString());
const enc = encodeURIComponent;

function crumbs(...parts) {
  document.getElementById('crumbs').replaceChildren(...parts.flatMap((p, i) => (i ? [' › ', p] : [p])));
}

function link(href, text) { return el('a', {href}, text); }

// ---- runs ----
async function showRuns() {
  const runs = await api('/api/runs');
  if (runs.length === 1) { location.replace('#/run/' + enc(runs[0].name)); return; }
  crumbs('runs');
  const t = el('table', {class: 'runs'}, el('tr', {}, el('th', {class: 'l'}, 'run'), el('th', {class: 'l'}, 'agents'),
    el('th', {}, 'episodes'), el('th', {}, 'SR %'), el('th', {}, 'IP'), el('th', {class: 'l'}, 'suite'),
    el('th', {class: 'l'}, 'folder')));
  const figure = (v) => (v === null || v === undefined ? '–' : v.toFixed(1));
  for (const r of runs) {
    t.append(el('tr', {class: 'clickable run-row', onclick: () => { location.hash = '#/run/' + enc(r.name); }},
      el('td', {class: 'l'}, r.name), el('td', {class: 'l'}, r.agents.join(', ')),
      el('td', {}, r.finished + ' / ' + r.planned + (r.live ? ' (running)' : '')),
      el('td', {class: 'run-sr'}, figure(r.sr)), el('td', {class: 'run-ip'}, figure(r.ip)),
      el('td', {class: 'l'}, r.suite || ''), el('td', {class: 'l muted'}, r.dir)));
  }
  show(el('h2', {}, 'Runs'), t, el('p', {}, link('#/leaderboard', 'Leaderboard'),
    ' — the agents of these runs ranked per suite, with the groups no paired test separates'));
}

// ---- leaderboard (mtg leaderboard) ----
async function showLeaderboard() {
  const lb = await api('/api/leaderboard');
  crumbs(link('#/', 'runs'), 'leaderboard');
  const ci = (c) => (c ? ' [' + c[0].toFixed(1) + ', ' + c[1].toFixed(1) + ']' : '');
  const parts = [el('h2', {}, 'Leaderboard')];
  for (const board of lb.boards) {
    // A suite's id, or a task set's identity for runs drawn from a set (not comparable across versions).
    parts.push(el('h3', {class: 'board-suite'}, board.suite.includes('@') ? 'Suite ' + board.suite : 'Runs on ' + board.suite));
    const t = el('table', {class: 'leaderboard'}, el('tr', {}, el('th', {}, 'rank'), el('th', {class: 'l'}, 'agent'),
      el('th', {}, 'episodes'), el('th', {}, 'SR % [95 % CI]'), el('th', {}, 'IP [95 % CI]'), el('th', {class: 'l'}, 'group')));
    for (const e of board.entrants) {
      const rank = e.rank_best === e.rank_worst ? String(e.rank_best) : e.rank_best + '–' + e.rank_worst;
      t.append(el('tr', {class: 'entrant'}, el('td', {}, rank), el('td', {class: 'l'}, e.label),
        el('td', {}, String(e.episodes)), el('td', {}, (e.sr === null ? '–' : e.sr.toFixed(1)) + ci(e.sr_ci)),
        el('td', {}, (e.ip === null ? '–' : e.ip.toFixed(1)) + ci(e.ip_ci)), el('td', {class: 'l'}, (e.groups || []).join(''))));
    }
    parts.push(t);
    for (const g of board.groups) {
      if (g.length > 1) parts.push(el('p', {class: 'tied'}, 'Tied (no paired test separates them, Holm ' +
        Math.round(100 * board.alpha) + ' %): ' + g.join(', ')));
    }
    for (const n of board.notes || []) parts.push(el('p', {class: 'muted'}, n));
  }
  show(...parts);
}

// ---- overview ----
function levelsOf(report) { return Object.keys(report.by_level).sort(); }

// The paper's Table 3 averages Levels 1–3 as the mean of the levels' figures: so does the Avg
// column here (the report's paper_avg, with its interval); Level 4, not in the paper's table,
// stands apart after it.
// A figure with its 95 % interval beneath (report keys x and x_ci).
function withCi(f, key) {
  const ci = f[key + '_ci'];
  return ci ? [fmt(f[key]), el('br'), el('small', {class: 'ci'}, fmt(ci[0]) + '–' + fmt(ci[1]))] : [fmt(f[key])];
}

function table3(o) {
  const report = o.report;
  const levels = levelsOf(report);
  const paperLevels = levels.filter((l) => Number(l) <= 3), apart = levels.filter((l) => Number(l) > 3);
  // The paper's Avg is over Levels 1–3; a run without some of them averages those it has, and says so.
  const avgLabel = paperLevels.length === 0 ? null :
    'Avg (L' + paperLevels[0] + (paperLevels.length > 1 ? '–' + paperLevels[paperLevels.length - 1] : '') + ')';
  const groups = [...paperLevels.map((l) => 'Level ' + l), ...(avgLabel ? [avgLabel] : []), ...apart.map((l) => 'Level ' + l)];
  const head1 = el('tr', {}, el('th', {class: 'l', rowspan: 2}, 'agent'),
    ...groups.map((g) => el('th', {colspan: 2, class: g.startsWith('Avg') ? 'avg' : ''}, g)), el('th', {rowspan: 2}, 'episodes'));
  const head2 = el('tr', {}, ...groups.flatMap(() => [el('th', {}, 'IP'), el('th', {}, 'SR (%)')]));
  const t = el('table', {class: 'results'}, head1, head2);
  const cells = (f, cls) => (f ? [el('td', {class: cls}, ...withCi(f, 'ip')), el('td', {class: cls}, ...withCi(f, 'sr'))]
    : [el('td', {class: cls}), el('td', {class: cls})]);
  const cellsOf = (byLevel, ls) => ls.flatMap((l) => cells((byLevel || {})[l], ''));
  for (const [agent, a] of Object.entries(report.by_agent)) {
    t.append(el('tr', {class: 'clickable agent-row', onclick: () => go(o.name, {agent})},
      el('td', {class: 'l'}, agent), ...cellsOf(a.by_level, paperLevels),
      // An agent without one of the run's levels has another average: blank, not mislabelled.
      ...(avgLabel ? cells(a.paper_avg && a.paper_avg.levels.join() === paperLevels.join() ? a.paper_avg : null, 'avg') : []),
      ...cellsOf(a.by_level, apart), el('td', {}, a.episodes)));
  }
  t.append(el('tr', {}, el('td', {class: 'l muted', colspan: 2 * groups.length + 2},
    'Beneath each figure its 95 % interval (Wilson for SR, a seeded bootstrap for IP). The paper’s Table 3, ' +
    'for reference (' + (avgLabel || 'Avg') + ' over the same levels as above):')));
  for (const p of o.paper) {
    // Over the same levels as the run's average, so the column compares like with like.
    const mean = (key) => paperLevels.reduce((sum, l) => sum + ((p.by_level || {})[l] || {})[key], 0) / paperLevels.length;
    const paperAvg = paperLevels.length === 3 ? {ip: p.ip, sr: p.sr} : {ip: mean('ip'), sr: mean('sr')};
    t.append(el('tr', {class: 'paper'}, el('td', {class: 'l'}, p.agent), ...cellsOf(p.by_level, paperLevels),
      ...(avgLabel ? cells(paperAvg, 'avg') : []), ...cellsOf({}, apart), el('td', {})));
  }
  return t;
}

const CAUSE_WORDS = {};  // filled from episode rows as they are seen (the API explains each cause)

function go(run, filters) {
  const q = Object.entries(filters).filter(([, v]) => v !== undefined && v !== '').map(([k, v]) => k + '=' + enc(v));
  location.hash = '#/run/' + enc(run) + '/episodes' + (q.length ? '?' + q.join('&') : '');
}

// A Sankey node id is "<column>:<label>" (level, stage, cause, outcome): each end of a flow
// becomes a filter of the episode list.
function filterOfNode(id, filters) {
  const column = id.slice(0, id.indexOf(':')), label = id.slice(id.indexOf(':') + 1);
  if (column === '0') filters.level = label.replace('Level ', '');
  if (column === '1') filters.stage = label;
  if (column === '2') filters.cause = label;
  if (column === '3') filters.success = label === 'success' ? '1' : '0';
  return filters;
}

async function showOverview(run, params) {
  const o = await api('/api/runs/' + enc(run));
  crumbs(link('#/', 'runs'), o.name);
  const r = o.report;
  // The failure section for all agents, or for the one chosen (?agent=A).
  const agents = Object.keys(r.by_agent);
  const chosen = agents.includes(params.get('agent')) ? params.get('agent') : '';
  const failures = chosen ? await api('/api/runs/' + enc(run) + '/report?agent=' + enc(chosen)) : r;
  const withAgent = (filters) => (chosen ? {...filters, agent: chosen} : filters);
  const parts = [];
  parts.push(el('p', {id: 'summary'}, o.finished + ' of ' + o.planned + ' episodes finished' +
    (o.live ? ' (running: this page refreshes as results arrive)' : '') + '. ' + r.scored + ' scored' +
    (r.errors ? ', ' + r.errors + ' given up (infrastructure)' : '') + '. SR ' + fmt(r.sr) + ' % ' + ciText(r.sr_ci) + ', IP ' + fmt(r.ip) + ' ' + ciText(r.ip_ci) + '. ',
    link('#/run/' + enc(run) + '/episodes', 'All episodes →')));
  if (r.excluded && r.excluded.length) {
    parts.push(el('p', {id: 'excluded', class: 'warn'}, r.excluded.length + ' episode(s) excluded by a person, outside ' +
      'every figure below (their results are unchanged; include one again from its page): ',
      ...r.excluded.flatMap((x, i) => [i ? ', ' : '', link('#/run/' + enc(run) + '/episode/' + x.episode, String(x.episode)),
        ' (' + x.reason + ')'])));
  }
  if (o.damage && o.damage.length) {
    parts.push(el('p', {id: 'damage', class: 'warn'}, 'The recording is damaged: ' + o.damage.join('; ') +
      '. Episodes whose messages lay there show less than happened; their results stand.'));
  }
  if (o.model_agents) {
    parts.push(el('p', {id: 'usage'}, 'Tokens: ' + r.tokens.input + ' in, ' + r.tokens.output + ' out; cost $' +
      r.cost_usd.toFixed(4) + '. Prompt version: ' + (o.prompt_versions.join(', ') || '–') + '.'));
  }
  parts.push(provenancePanel(o));
  parts.push(el('h2', {}, 'Results by level (click an agent for its episodes)'), table3(o),
    el('p', {class: 'note'}, 'IP: intermediate points (25 per milestone: source reached, item picked, destination ' +
      'reached, placed as asked; Level 3 averages its sub-tasks). SR: success rate.'));
  parts.push(comparePicker(o, agents));
  const repeats = repeatsSection(o);
  if (repeats) parts.push(...repeats);
  if (agents.length > 1) {
    const pick = el('select', {id: 'failure-agent'}, el('option', {value: ''}, 'all agents'),
      ...agents.map((a) => el('option', {value: a}, a)));
    pick.value = chosen;
    pick.addEventListener('change', () => { location.hash = '#/run/' + enc(run) + (pick.value ? '?agent=' + enc(pick.value) : ''); });
    parts.push(el('p', {id: 'failure-of'}, 'Failures of ', pick,
      chosen ? ' (' + failures.scored + ' scored episodes, SR ' + fmt(failures.sr) + ' % ' + ciText(failures.sr_ci) +
        ', IP ' + fmt(failures.ip) + ' ' + ciText(failures.ip_ci) + ')' : ''));
  }
  const sankey = el('div', {id: 'sankey'}, 'Loading the Sankey…');
  parts.push(el('h2', {}, 'Failure Sankey' + (chosen ? ' of ' + chosen : '') +
    ': task level → stage reached → cause → outcome (click a flow for its episodes)'), sankey);
  const causes = el('table', {class: 'causes'}, el('tr', {}, el('th', {class: 'l'}, 'cause'), el('th', {class: 'l'}, 'meaning'),
    el('th', {}, 'episodes')));
  for (const [cause, n] of Object.entries(failures.causes).sort((a, b) => b[1] - a[1])) {
    causes.append(el('tr', {class: 'clickable cause-row', onclick: () => go(run, withAgent({cause}))}, el('td', {class: 'l'}, cause),
      el('td', {class: 'l cause-text', 'data-cause': cause}, ''), el('td', {}, n)));
  }
  parts.push(el('h2', {}, 'Failure causes' + (chosen ? ' of ' + chosen : '')),
    Object.keys(failures.causes).length ? causes : el('p', {}, 'No failures.'));
  show(...parts);
  fillCauseWords(run).catch(unlessStale);
  const svg = await api('/api/runs/' + enc(run) + '/sankey.svg' + (chosen ? '?agent=' + enc(chosen) : ''));
  sankey.innerHTML = svg;
  window.mtgSankey = performance.now();
  for (const path of sankey.querySelectorAll('path.flow')) {
    path.addEventListener('click', () => go(run, withAgent(filterOfNode(path.dataset.target, filterOfNode(path.dataset.source, {})))));
  }
  scheduleRefresh(o.live);
}

// "Compare against": another agent of this run as the baseline, or another run served.
function comparePicker(o, agents) {
  const pick = el('select', {id: 'baseline'}, el('option', {value: ''}, 'choose a baseline…'),
    ...(agents.length > 1 ? agents.map((a) => el('option', {value: 'agent:' + a}, 'agent ' + a + ' of this run')) : []));
  api('/api/runs').then((runs) => {
    for (const r of runs) if (r.name !== o.name) pick.append(el('option', {value: 'run:' + r.name}, 'run ' + r.name));
  }).catch(() => {});
  pick.addEventListener('change', () => {
    const [kind, name] = [pick.value.slice(0, pick.value.indexOf(':')), pick.value.slice(pick.value.indexOf(':') + 1)];
    if (kind === 'agent') location.hash = '#/comparison?a=' + enc(o.name) + '&baseline=' + enc(name);
    if (kind === 'run') location.hash = '#/comparison?a=' + enc(name) + '&b=' + enc(o.name);
  });
  return el('p', {id: 'compare-with'}, 'Paired comparison on the same tasks, against ', pick);
}

const pText = (p) => (p < 0.001 ? p.toExponential(1) : p.toFixed(3));
const signed = (v) => (v > 0 ? '+' : '') + fmt(v);

async function showComparison(params) {
  const q = new URLSearchParams();
  for (const k of ['a', 'b', 'agent', 'baseline']) if (params.get(k)) q.set(k, params.get(k));
  const c = await api('/api/compare?' + q);
  crumbs(link('#/', 'runs'), link('#/run/' + enc(params.get('a')), params.get('a')), 'comparison');
  const parts = [c.warning ? el('p', {class: 'warn', id: 'compare-warning'}, c.warning) : null, el('p', {class: 'note'}, 'Differences are B − A on the episodes both ran (the same task and repeat), ' +
    'with 95 % intervals; p-values (exact McNemar for SR, sign-flip permutation for IP) after Holm over ' +
    c.comparisons.length + ' comparison' + (c.comparisons.length === 1 ? '' : 's') + ' (docs/statistics.md).')];
  for (const x of c.comparisons) {
    const head = el('tr', {}, ...['level', 'pairs', 'SR A', 'SR B', 'SR B−A [95 % CI]', 'McNemar p', 'IP A', 'IP B',
      'IP B−A [95 % CI]', 'permutation p'].map((h) => el('th', {}, h)));
    const t = el('table', {class: 'comparison'}, head);
    for (const [level, l] of Object.entries(x.levels)) {
      t.append(el('tr', {class: level === 'all' ? 'all' : ''}, el('td', {class: 'l'}, level === 'all' ? 'all' : 'L' + level),
        el('td', {}, l.pairs), el('td', {}, fmt(l.sr_a)), el('td', {}, fmt(l.sr_b)),
        el('td', {}, signed(l.sr_diff) + ' [' + signed(l.sr_diff_ci[0]) + ', ' + signed(l.sr_diff_ci[1]) + ']'),
        el('td', {class: l.sr_p_holm < c.alpha ? 'ok' : 'muted'}, pText(l.sr_p_holm)),
        el('td', {}, fmt(l.ip_a)), el('td', {}, fmt(l.ip_b)),
        el('td', {}, signed(l.ip_diff) + ' [' + signed(l.ip_diff_ci[0]) + ', ' + signed(l.ip_diff_ci[1]) + ']'),
        el('td', {class: l.ip_p_holm < c.alpha ? 'ok' : 'muted'}, pText(l.ip_p_holm))));
    }
    const all = x.levels.all;
    const verdict = (m, name) => {
      const p = all[m + '_p_holm'], d = all[m + '_diff'];
      if (p < c.alpha) return name + ': B is ' + (d < 0 ? 'lower' : 'higher') + ' by ' + fmt(Math.abs(d)) + ' points, significant (p ' + pText(p) + ').';
      const det = all[m + '_detectable'];
      return name + ': not significant (p ' + pText(p) + '): these pairs cannot tell A and B apart' +
        (det !== null ? '; a difference of about ' + fmt(det) + ' points would show (80 % power).' : '.');
    };
    const flips = (list, count, label) => el('details', {class: 'flips'}, el('summary', {}, count + ' ' + label),
      ...list.map((f) => el('div', {}, el('a', {class: 'flip', href: '#/compare?a=' + enc(x.a.run + '/' + f.episode_a) + '&b=' +
        enc(x.b.run + '/' + f.episode_b)}, f.task + ' (L' + f.level + '): episodes ' + f.episode_a + ' / ' + f.episode_b))),
      count > list.length ? el('div', {class: 'muted'}, '… the first ' + list.length + ' shown') : null);
    parts.push(el('h2', {}, 'B ' + x.b.run + ' / ' + x.b.agent + ' against A ' + x.a.run + ' / ' + x.a.agent),
      el('p', {}, x.pairs + ' paired episodes' + (x.unpaired_a + x.unpaired_b ? ' (' + x.unpaired_a + ' of A and ' +
        x.unpaired_b + ' of B without a partner, left out' +
        (x.unpaired_a_excluded_in_b ? '; ' + x.unpaired_a_excluded_in_b + " of A's because B's episode was excluded" : '') +
        (x.unpaired_b_excluded_in_a ? '; ' + x.unpaired_b_excluded_in_a + " of B's because A's episode was excluded" : '') +
        ')' : '') + '.'),
      ...['a', 'b'].map((side) => {
        const e = x['excluded_' + side];
        if (!e || !e.episodes) return null;
        const why = Object.entries(e.reasons).map(([r, n]) => n + ' "' + r + '"').join('; ');
        return el('p', {class: 'excluded-line'}, 'Excluded by a person from ' + side.toUpperCase() + ': ' + e.episodes +
          ' episode(s) (' + why + '), outside every figure here.');
      }),
      t, el('p', {class: 'verdict-line'}, verdict('sr', 'SR')), el('p', {class: 'verdict-line'}, verdict('ip', 'IP')),
      flips(x.regressions, x.regression_count, 'regressions (A succeeded, B failed): click one for both side by side'),
      flips(x.improvements, x.improvement_count, 'improvements (B succeeded, A failed)'));
  }
  show(...parts);
}

// With repeats: pass@k and pass^k per agent, then the task × agent grid of k-of-n (folded; a cell
// opens that agent's episodes of that task). Null without repeats.
function repeatsSection(o) {
  const grid = o.grid;
  if (!grid) return null;
  const withRepeats = Object.entries(o.report.by_agent).filter(([, a]) => a.repeats);
  const k = Math.max(...withRepeats.map(([, a]) => a.repeats.pass_at_k.length));
  const summary = el('table', {class: 'repeats'}, el('tr', {}, el('th', {class: 'l'}, 'agent'), el('th', {}, 'tasks'),
    el('th', {}, 'tries each'), ...Array.from({length: k}, (_, i) => el('th', {}, 'pass@' + (i + 1))),
    el('th', {}, 'pass^' + k), el('th', {class: 'l'}, 'tasks by successes')));
  for (const [agent, a] of withRepeats) {
    const r = a.repeats, n = r.episodes_per_task;
    summary.append(el('tr', {}, el('td', {class: 'l'}, agent), el('td', {}, r.tasks),
      el('td', {}, n[0] === n[1] ? n[0] : n[0] + '–' + n[1]),
      ...Array.from({length: k}, (_, i) => el('td', {}, fmt(r.pass_at_k[i]))),
      el('td', {}, fmt(r.pass_hat_k[k - 1])),
      el('td', {class: 'l'}, Object.entries(r.k_of_n).map(([kn, t]) => kn + ': ' + t).join(' · '))));
  }
  const table = el('table', {class: 'grid'}, el('tr', {}, el('th', {class: 'l'}, 'task'), el('th', {}, 'level'),
    ...grid.agents.map((a) => el('th', {}, a))));
  for (const row of grid.rows) {
    table.append(el('tr', {}, el('td', {class: 'l'}, row.task), el('td', {}, row.level),
      ...row.cells.map((cell, i) => (cell ? el('td', {class: 'clickable k-of-n', 'data-share': cell[0] / cell[1],
        onclick: () => go(o.name, {task: row.task, agent: grid.agents[i]})}, cell[0] + ' of ' + cell[1]) : el('td', {})))));
  }
  return [el('h2', {}, 'Repeats'), summary,
    el('p', {class: 'note'}, 'pass@k: the share of tasks an agent gets right at least once in k tries; pass^k: right in ' +
      'all k (both estimated from every try of a task).'),
    el('details', {id: 'grid'}, el('summary', {}, 'Tasks × agents: successes of tries (' + grid.rows.length +
      ' tasks; click a cell for its episodes)'), table)];
}

// What made the run (plan.json's provenance, sessions.jsonl, the plan's settings): folded, since a
// reader wants it when citing or reproducing a figure, not at every look.
function provenancePanel(o) {
  const p = o.provenance, st = o.settings || {};
  const rows = [];
  const row = (label, ...value) => rows.push(el('tr', {}, el('th', {class: 'l'}, label), el('td', {class: 'l'}, ...value)));
  if (p) {
    row('mtg', p.mtg_version + ' (revision ' + p.git_revision + ')');
    row('command', el('code', {}, (p.command || []).join(' ')));
    row('planned', p.planned_at + ' on ' + p.host);
  } else {
    row('mtg', 'unknown: this run was planned before runs recorded what made them');
  }
  for (const s of o.sessions || []) {
    if (s.event === 'start') {
      row(s.resumed ? 'resumed' : 'started', s.at + ' on ' + s.host + ' (mtg ' + s.mtg_version + ', ' + s.git_revision + ')');
    } else if (s.event === 'end') {
      row('ended', s.at + ' on ' + s.host + ': ' + s.ended + ', ' + s.episodes_done + ' episodes finished' +
        (s.given_up ? ', ' + s.given_up + ' given up' : ''));
    }
  }
  if ((o.workers || []).length) row('workers', o.workers.join(', '));
  row('task set', st.tasks_db || '–', p ? ' (config hash ' + p.task_set.config_hash + ')' : '');
  if (p) row('dataset', Object.entries(p.dataset || {}).map(([scene, digest]) => scene + ' ' + digest).join(', ') || '–');
  row('seed', String(st.seed) + ' · repeat ' + st.repeat + ' · limit ' + (st.limit || 'all') + ' per scene and level · ' +
    'step limit ' + st.step_limit + ' · images ' + (o.render ? st.image_size : 'none') + ' · scenes ' +
    ((st.scenes || []).join(', ') || 'all'));
  if (o.prompt_versions && o.prompt_versions.length) row('prompt version', o.prompt_versions.join(', '));
  if (p && p.model_settings) row('model settings', el('code', {}, JSON.stringify(p.model_settings)));
  return el('details', {id: 'provenance'}, el('summary', {}, 'How this run was made' +
    (p ? ': mtg ' + p.mtg_version + ' ' + p.git_revision + ', planned ' + p.planned_at : '')),
    el('table', {class: 'provenance'}, ...rows));
}

async function fillCauseWords(run) {
  for (const cell of document.querySelectorAll('.cause-text')) {
    const cause = cell.dataset.cause;
    if (!CAUSE_WORDS[cause]) {
      const page = await api('/api/runs/' + enc(run) + '/episodes?limit=1&cause=' + enc(cause));
      if (page.rows.length) CAUSE_WORDS[cause] = page.rows[0].cause_text;
    }
    cell.textContent = CAUSE_WORDS[cause] || '';
  }
}

// A live run's page is redrawn every 2 s, but never under a reader's hands: while a field has focus
// or holds what they typed or chose and have not applied, the redraw waits.
function readerIsEditing() {
  const active = document.activeElement;
  if (active && main.contains(active) && ['INPUT', 'SELECT', 'TEXTAREA'].includes(active.tagName)) return true;
  return [...main.querySelectorAll('input, select, textarea')].some((f) => f.value !== f.dataset.shown);
}

function scheduleRefresh(live) {
  clearTimeout(refreshTimer);
  document.getElementById('live').textContent = live ? 'live' : '';
  if (live) refreshTimer = setTimeout(() => (readerIsEditing() ? scheduleRefresh(true) : route()), 2000);
}

// ---- episode list ----
// `q` searches task ids (a part is enough) and texts; `task` is an exact id (links from other pages).
const FILTERS = ['q', 'agent', 'level', 'scene', 'stage', 'cause', 'success', 'status', 'task'];
const LIST_KEYS = [...FILTERS, 'sort', 'order'];  // what the list is: kept when moving from episode to episode
const COLUMNS = [['episode', 'episode'], ['agent', 'agent'], ['level', 'level'], ['scene', 'scene'],
  ['task', 'task'], ['text', 'task text'], ['verdict', 'verdict'], ['ip', 'IP'], ['stage', 'stage reached'],
  ['cause', 'cause'], ['steps', 'steps']];
const PAGE_SIZES = [25, 100, 500];

function listQuery(params) {
  const q = new URLSearchParams();
  for (const k of LIST_KEYS) if (params.get(k)) q.set(k, params.get(k));
  return q;
}

async function showEpisodes(run, params) {
  const o = await api('/api/runs/' + enc(run));
  crumbs(link('#/', 'runs'), link('#/run/' + enc(run), o.name), 'episodes');
  const offset = Number(params.get('offset') || 0);
  const limit = PAGE_SIZES.includes(Number(params.get('limit'))) ? Number(params.get('limit')) : 100;
  const q = listQuery(params);
  q.set('offset', offset);
  q.set('limit', limit);
  const page = await api('/api/runs/' + enc(run) + '/episodes?' + q);
  const r = o.report;
  const choices = {
    agent: Object.keys(r.by_agent), level: levelsOf(r), stage: Object.keys(r.stages),
    cause: ['success', ...Object.keys(r.causes)], success: ['1', '0'], status: ['scored', 'error'],
  };
  const form = el('form', {class: 'filters'});
  for (const f of FILTERS) {
    let input;
    if (choices[f]) {
      input = el('select', {name: f}, el('option', {value: ''}, 'any'),
        ...choices[f].map((v) => el('option', {value: v}, f === 'success' ? (v === '1' ? 'yes' : 'no') : v)));
    } else {
      input = el('input', {name: f, size: f === 'q' ? 24 : 14, placeholder: f === 'q' ? 'task id, words or replies' : ''});
    }
    input.value = params.get(f) || '';
    if (f === 'task' && !params.get('task')) continue;  // only shown when a link set it
    form.append(el('label', {}, f === 'q' ? 'search' : f, input));
  }
  const sizes = el('select', {name: 'limit'}, ...PAGE_SIZES.map((n) => el('option', {value: n}, n + ' rows')));
  sizes.value = limit;
  form.append(el('label', {}, 'show', sizes), el('button', {}, 'Filter'));
  const withList = (changes) => {
    const next = listQuery(params);
    for (const [k, v] of Object.entries(changes)) { if (v === '' || v === undefined) next.delete(k); else next.set(k, v); }
    return next;
  };
  form.addEventListener('submit', (ev) => {
    ev.preventDefault();
    const changes = {limit: form.elements.limit.value};
    for (const f of FILTERS) if (form.elements[f]) changes[f] = form.elements[f].value;
    location.hash = '#/run/' + enc(run) + '/episodes?' + withList(changes);
  });
  sizes.addEventListener('change', () => form.requestSubmit());
  // A click on a column sorts by it; a second click turns the order round.
  const sort = params.get('sort') || 'episode', order = params.get('order') || 'asc';
  const t = el('table', {class: 'episodes'}, el('tr', {}, ...COLUMNS.map(([key, label]) => {
    const active = key === sort;
    const next = withList({sort: key, order: active && order === 'asc' ? 'desc' : 'asc', limit});
    return el('th', {class: 'l sortable' + (active ? ' sorted' : ''), 'data-sort': key},
      link('#/run/' + enc(run) + '/episodes?' + next, label + (active ? (order === 'asc' ? ' ▲' : ' ▼') : '')));
  })));
  const listOf = listQuery(params).toString();
  for (const e of page.rows) {
    CAUSE_WORDS[e.cause] = e.cause_text;
    t.append(el('tr', {class: 'clickable episode-row', 'data-episode': e.episode_id,
      onclick: () => { location.hash = '#/run/' + enc(run) + '/episode/' + e.episode_id + (listOf ? '?' + listOf : ''); }},
      el('td', {class: 'l'}, e.episode_id), el('td', {class: 'l'}, e.agent), el('td', {class: 'l'}, e.level),
      el('td', {class: 'l'}, e.scene), el('td', {class: 'l'}, e.task_id),
      el('td', {class: 'l task-text', title: e.task_text}, e.task_text),
      el('td', {class: 'l ' + (e.status !== 'scored' ? 'muted' : e.success ? 'ok' : 'fail')},
        e.status !== 'scored' ? 'error' : e.success ? 'success' : 'failure', markBadges(e.marks)),
      el('td', {}, fmt(e.ip)), el('td', {class: 'l'}, e.stage), el('td', {class: 'l', title: e.cause_text}, e.cause),
      el('td', {}, e.steps)));
  }
  const pager = el('div', {class: 'pager'});
  const pageTo = (off) => {
    location.hash = '#/run/' + enc(run) + '/episodes?' + withList({offset: off, limit});
  };
  if (offset > 0) pager.append(el('button', {onclick: () => pageTo(Math.max(0, offset - limit))}, '← previous'));
  if (offset + limit < page.total) pager.append(el('button', {onclick: () => pageTo(offset + limit)}, 'next →'));
  show(form, el('p', {id: 'count'}, page.total + ' episode(s)' +
    (page.total > limit ? ', ' + (offset + 1) + '–' + Math.min(offset + limit, page.total) + ' shown' : '')), t, pager);
  scheduleRefresh(o.live);
}

// ---- one episode ----
function verdictBanner(e) {
  const v = e.result;
  const r = e.row;
  if (!v && r && r.attempt === e.attempt) {
    // The results hold the verdict the recording lacks (lost where it is damaged).
    if (r.status !== 'scored') {
      return el('div', {class: 'banner fail', id: 'verdict'}, el('b', {}, 'Given up'), ' by the infrastructure: ' + r.detail);
    }
    return el('div', {class: 'banner ' + (r.success ? 'ok' : 'fail'), id: 'verdict'},
      el('b', {}, r.success ? 'Success' : 'Failure'), ' · IP ' + fmt(r.ip) + ' · ' + r.steps + ' step(s), ' +
      r.invalid_actions + ' invalid (from the results; the recording lacks the judge\'s message). ',
      r.success ? '' : el('span', {}, 'Cause: ', el('b', {}, r.cause), ' — ' + r.cause_text + '. '),
      'Furthest stage: ' + r.stage + ' (' + r.stage_text + ').');
  }
  if (!v) return el('div', {class: 'banner', id: 'verdict'}, 'No verdict recorded for this attempt (yet).');
  return el('div', {class: 'banner ' + (v.success ? 'ok' : 'fail'), id: 'verdict'},
    el('b', {}, v.success ? 'Success' : 'Failure'), ' · IP ' + fmt(v.ip) + ' · ' + v.steps + ' step(s), ' +
    v.invalid_actions + ' invalid. ',
    v.success ? '' : el('span', {}, 'Cause: ', el('b', {}, v.cause), ' — ' + v.cause_text + '. '),
    'Furthest stage: ' + v.stage + ' (' + v.stage_text + ').',
    v.subtasks.length > 1 ? el('div', {class: 'muted'}, 'Sub-tasks: ' +
      v.subtasks.map((s, i) => (i + 1) + ': IP ' + fmt(s.ip) + (s.success ? ' ✓' : '')).join(', ')) : null,
    v.detail ? el('div', {class: 'muted'}, v.detail) : null);
}

// A model's request as it was sent: every message in order, images as thumbnails (full size on a
// click), folded; the prompt version and parameters in the summary line.
function requestBlock(req, a) {
  if (!req) return null;
  if (req.error) return el('div', {class: 'fail'}, 'Request: ' + req.error);
  const images = req.messages.reduce((n, m) => n + m.images.length, 0);
  const messages = req.messages.map((m) => el('div', {class: 'msg msg-' + m.role},
    el('div', {class: 'muted'}, m.role + (m.role === 'system' ? '' : ' · step ' + (m.step + 1)) +
      (m.images.length ? ' · ' + m.images.length + ' image(s)' : '')),
    m.missing ? el('div', {class: 'fail'}, 'not in the recording (damaged or cut short)') : el('pre', {class: 'msg-text'}, m.text),
    m.images.length ? el('div', {class: 'msg-images'}, ...m.images.map((i) => i.url
      ? el('a', {href: i.url, target: '_blank', title: 'sent ' + i.width + '×' + i.height + ', sha256 ' + i.sha256},
        el('img', {src: i.url, loading: 'lazy', alt: 'image ' + (i.index + 1) + ' of step ' + (i.step + 1)}))
      : el('span', {class: 'muted'}, '[image not recorded]'))) : null));
  const p = req.params || {};
  return el('details', {class: 'request'},
    el('summary', {}, 'What the model received: ' + req.messages.length + ' message(s), ' + images + ' image(s)' +
      (a && a.prompt_version ? ', prompts ' + a.prompt_version : '') +
      (p.temperature !== undefined ? ', temperature ' + p.temperature + ', max ' + p.max_output_tokens + ' output tokens' : '')),
    ...messages);
}

function stepBlock(s) {
  const a = s.action;
  const r = s.reply;
  // Built-in agents, a person at the play desk and a replayed answer call no model: no tokens, no cost.
  const model = a && !['builtin', 'human', 'replay'].includes(a.provider);
  return el('div', {class: 'step', 'data-step': s.step},
    el('h3', {}, s.done ? 'Final state (step ' + s.step + ')' : 'Step ' + (s.step + 1)),
    s.observation ? renderObservation(s.observation, {chosen: a && a.parsed_key, told: s.step === 0}) : el('div', {class: 'muted'}, 'no observation recorded'),
    requestBlock(s.request, a),
    a ? el('div', {class: 'reply'},
      el('div', {}, 'Answer: ', el('b', {class: 'parsed-key'}, a.parsed_key || '(no key)'),
        r && r.meaning ? el('span', {class: 'key-meaning'}, ' — ' + r.meaning) : '',
        a.format_ok ? '' : el('span', {class: 'fail'}, ' unreadable'),
        a.error ? el('span', {class: 'fail'}, ' provider error: ' + a.error) : '',
        model ? el('span', {class: 'muted usage'}, ' · ' + a.provider + (a.model ? ' ' + a.model : '') +
          ' · ' + a.input_tokens + '+' + a.output_tokens + ' tokens · ' + Math.round(a.latency_ms) + ' ms · $' +
          a.cost_usd.toFixed(4) + (a.cache_hit ? ' · cache hit' : '')) : ''),
      model || a.raw_reply !== a.parsed_key ? el('div', {},
        model ? el('div', {class: 'muted'}, 'Full reply:') : null, el('pre', {class: 'raw-reply'}, a.raw_reply)) : null) : null,
    ...s.judge.map((j) => el('div', {class: 'judge'}, '⚑ ' + (j.text || j.kind) + (j.kind === 'milestone' ? ' (IP ' + fmt(j.ip) + ')' : ''))));
}

function episodeHeader(e) {
  const t = e.task || (e.row ? {level: e.row.level, scene: e.row.scene, task_id: e.row.task_id,
    task_type: e.row.task_type} : {});
  return el('div', {},
    el('h2', {}, 'Episode ' + e.episode_id + ' · ' + (e.agent || (e.row && e.row.agent) || '')),
    el('div', {class: 'muted', id: 'task-line'}, 'Level ' + t.level + ' · ' + t.scene + ' · ' + t.task_id + ' · ' + t.task_type +
      ' · attempt ' + e.attempt + (e.attempts.length > 1 ? ' of ' + e.attempts.length : '')),
    el('pre', {class: 'task-text'}, t.text || ''),
    verdictBanner(e));
}

// The episode page's keys (previous / next); replaced by each episode page, off elsewhere.
let episodeKeys = null;
document.addEventListener('keydown', (ev) => { if (episodeKeys) episodeKeys(ev); });

// The strip of steps atop an episode: one thumbnail (its first image) or number per step; a click,
// or the keys ↓ ↑ (j k), moves to a step and makes the address that step's link without redrawing.
// Steps are linked by the number the page shows (…/step/8 is "Step 8").
function stepStrip(e, stepHash) {
  const strip = el('div', {class: 'step-strip', id: 'step-strip'});
  const blocks = () => [...document.querySelectorAll('#main .step')];
  let current = -1;
  const goTo = (i) => {
    const all = blocks();
    if (i < 0 || i >= all.length) return;
    current = i;
    all[i].scrollIntoView({block: 'start'});
    for (const [k, cell] of [...strip.children].entries()) cell.classList.toggle('current', k === i);
    history.replaceState(null, '', stepHash(Number(all[i].dataset.step) + 1));
  };
  e.steps.forEach((s, i) => {
    const img = s.observation && s.observation.images && s.observation.images[0];
    strip.append(el('a', {class: 'step-thumb', href: stepHash(s.step + 1), title: 'step ' + (s.step + 1),
      onclick: (ev) => { ev.preventDefault(); goTo(i); }},
    img ? el('img', {src: img.url, loading: 'lazy', alt: 'step ' + (s.step + 1)}) : el('span', {}, String(s.step + 1))));
  });
  return {strip, goTo, next: () => goTo(current + 1), previous: () => goTo(Math.max(0, current - 1)),
    index: (step) => e.steps.findIndex((s) => s.step + 1 === step)};
}

// The episode as one JSON file (what the page shows), for a bug report or a notebook.
let episodeBlobUrl = null;  // one at a time: the last episode page's is let go
function episodeDownload(run, e) {
  if (episodeBlobUrl) URL.revokeObjectURL(episodeBlobUrl);
  episodeBlobUrl = URL.createObjectURL(new Blob([JSON.stringify(e, null, 1)], {type: 'application/json'}));
  return el('a', {id: 'episode-json', href: episodeBlobUrl, download: run + '-episode-' + e.episode_id +
    '-attempt-' + e.attempt + '.json'}, 'Download this episode (JSON)');
}

// A list row's marks, after its verdict: ⚑ flagged, #tags, and "excluded" (outside the figures).
function markBadges(m) {
  if (!m) return null;
  const words = [m.flagged ? '⚑' : '', ...m.tags.map((t) => '#' + t), m.excluded ? 'excluded' : ''].filter(Boolean);
  return words.length ? el('span', {class: 'mark-badge'}, ' ' + words.join(' ')) : null;
}

// An episode's marks now, their trail (who, when, what, why), and, where a server keeps them, a
// form to add one; an exported site shows them only.
async function marksBox(run, id, box) {
  const m = await api('/api/runs/' + enc(run) + '/marks?episode=' + id);
  const now = m.marks[String(id)] || {flagged: false, tags: [], excluded: false, reason: ''};
  const state = el('div', {id: 'marks-now'}, now.flagged ? '⚑ flagged' : 'not flagged',
    ' · tags: ' + (now.tags.join(', ') || 'none') + ' · ',
    now.excluded ? el('b', {}, 'excluded from the statistics: ' + now.reason) : 'counted in the statistics');
  const trail = el('details', {id: 'marks-trail'}, el('summary', {}, 'Who marked it (' + m.trail.length + ')'),
    ...m.trail.map((e) => el('div', {class: 'muted'}, e.at + ' · ' + e.who + ': ' + e.action + (e.tag ? ' ' + e.tag : '') +
      (e.reason ? ' — ' + e.reason : ''))));
  if (window.mtgStaticApi) {
    box.replaceChildren(el('h3', {}, 'Marks'), state, trail);
    return;
  }
  const who = el('input', {name: 'who', size: 12, placeholder: 'your name'});
  who.value = localStorage.getItem('mtg-who') || '';
  const action = el('select', {name: 'action'}, ...['flag', 'unflag', 'tag', 'untag', 'exclude', 'include'].map((a) =>
    el('option', {value: a}, a)));
  const tag = el('input', {name: 'tag', size: 10, placeholder: 'tag'});
  const reason = el('input', {name: 'reason', size: 36, placeholder: 'why (required to exclude or include)'});
  const message = el('span', {id: 'mark-message'});
  const form = el('form', {id: 'mark-form'}, who, ' ', action, ' ', tag, ' ', reason, ' ', el('button', {}, 'Save'), ' ', message);
  form.addEventListener('submit', async (ev) => {
    ev.preventDefault();
    message.textContent = '';
    localStorage.setItem('mtg-who', who.value);
    const res = await fetch('/api/runs/' + enc(run) + '/marks', {method: 'POST', headers: {'Content-Type': 'application/json'},
      body: JSON.stringify({episode: Number(id), action: action.value, tag: tag.value, reason: reason.value, who: who.value})});
    const body = await res.json();
    if (!res.ok) {
      message.textContent = body.error;
      message.className = 'fail';
      return;
    }
    marksBox(run, id, box).catch(unlessStale);
  });
  box.replaceChildren(el('h3', {}, 'Marks'), state, form, trail);
  for (const f of box.querySelectorAll('input, select')) f.dataset.shown = f.value;
}

async function showEpisode(run, id, params, step) {
  const attempt = params.get('attempt');
  const e = await api('/api/runs/' + enc(run) + '/episodes/' + id + (attempt ? '?attempt=' + attempt : ''));
  const back = listQuery(params).toString();
  crumbs(link('#/', 'runs'), link('#/run/' + enc(run), run),
    link('#/run/' + enc(run) + '/episodes' + (back ? '?' + back : ''), 'episodes'), 'episode ' + id);
  const truthBox = el('div', {id: 'truth'});
  const truthButton = el('button', {onclick: async () => {
    const t = await api('/api/runs/' + enc(run) + '/episodes/' + id + '/truth?attempt=' + e.attempt);
    truthBox.replaceChildren(el('div', {class: 'muted'}, 'Never shown to the agent:'),
      el('div', {}, 'Oracle plan: ', el('b', {}, t.oracle_plan.join(' → '))),
      el('pre', {}, 'Goal: ' + JSON.stringify(t.goal, null, 1)));
  }}, 'Show the goal and the oracle plan');
  const compare = el('div', {id: 'others'});
  const attempts = e.attempts.length > 1 ? el('div', {}, 'Attempts: ', ...e.attempts.map((k) =>
    el('a', {href: '#/run/' + enc(run) + '/episode/' + id + '?attempt=' + k, style: 'margin-right:6px'}, String(k)))) : null;
  // Previous / next within the list this episode was opened from (its filters, search and order).
  const list = listQuery(params).toString();
  const around = await api('/api/runs/' + enc(run) + '/episodes/' + id + '/neighbours' + (list ? '?' + list : ''));
  const to = (other) => '#/run/' + enc(run) + '/episode/' + other + (list ? '?' + list : '');
  const nav = el('div', {class: 'pager', id: 'neighbours'},
    around.previous !== null ? link(to(around.previous), '← previous') : el('span', {class: 'muted'}, '← previous'),
    ' ', el('span', {class: 'muted'}, around.position !== null ? (around.position + 1) + ' of ' + around.total : ''),
    ' ', around.next !== null ? link(to(around.next), 'next →') : el('span', {class: 'muted'}, 'next →'),
    el('span', {class: 'muted'}, '  (keys: ← → episodes, ↓ ↑ or j k steps)'));
  const query = location.hash.includes('?') ? location.hash.slice(location.hash.indexOf('?')) : '';
  const steps = stepStrip(e, (k) => '#/run/' + enc(run) + '/episode/' + id + '/step/' + k + query);
  episodeKeys = (ev) => {
    if (ev.target.closest && ev.target.closest('input, textarea, select')) return;
    if (ev.key === 'ArrowLeft' && around.previous !== null) location.hash = to(around.previous);
    if (ev.key === 'ArrowRight' && around.next !== null) location.hash = to(around.next);
    if (ev.key === 'ArrowDown' || ev.key === 'j') { ev.preventDefault(); steps.next(); }
    if (ev.key === 'ArrowUp' || ev.key === 'k') { ev.preventDefault(); steps.previous(); }
  };
  const marks = el('div', {id: 'marks'});
  show(episodeHeader(e), nav, attempts, el('div', {}, truthButton, ' ', episodeDownload(run, e)), truthBox, compare, marks,
    e.missing ? el('p', {id: 'missing', class: 'warn'}, e.missing) : null,
    steps.strip,
    ...e.steps.map(stepBlock),
    e.errors.length ? el('div', {}, el('h2', {}, 'Errors reported during the episode'),
      ...e.errors.map((x) => el('div', {class: 'error'}, x.severity + ' from ' + x.source + ': ' + x.message))) : null);
  if (step !== null && steps.index(step) >= 0) steps.goTo(steps.index(step));
  if (e.task) listOthers(run, id, e.task.task_id, compare).catch(unlessStale);
  marksBox(run, id, marks).catch(unlessStale);
}

// Other episodes of the same task, in every run served: links to compare side by side.
async function listOthers(run, id, taskId, box) {
  const runs = await api('/api/runs');
  const links = [];
  for (const r of runs) {
    const page = await api('/api/runs/' + enc(r.name) + '/episodes?limit=20&task=' + enc(taskId));
    for (const other of page.rows) {
      if (r.name === run && String(other.episode_id) === String(id)) continue;
      links.push(el('a', {class: 'compare-link', href: '#/compare?a=' + enc(run + '/' + id) + '&b=' +
        enc(r.name + '/' + other.episode_id), style: 'margin-right:10px'},
        (runs.length > 1 ? r.name + ': ' : '') + other.agent + ' (episode ' + other.episode_id + ', ' +
        (other.success ? 'success' : other.cause || 'failure') + ')'));
    }
  }
  if (links.length) box.replaceChildren('Same task, side by side with: ', ...links);
}

async function showCompare(params) {
  const sides = ['a', 'b'].map((k) => {
    const v = params.get(k) || '';
    const cut = v.lastIndexOf('/');
    return {run: v.slice(0, cut), id: v.slice(cut + 1)};
  });
  const episodes = await Promise.all(sides.map((s) => api('/api/runs/' + enc(s.run) + '/episodes/' + s.id)));
  crumbs(link('#/', 'runs'), 'side by side');
  const steps = Math.max(...episodes.map((e) => e.steps.length));
  const grid = el('div', {class: 'compare'});
  episodes.forEach((e, i) => grid.append(el('div', {}, el('div', {class: 'muted'}, sides[i].run),
    link('#/run/' + enc(sides[i].run) + '/episode/' + e.episode_id, 'open'), episodeHeader(e))));
  for (let k = 0; k < steps; ++k) {
    for (const e of episodes) grid.append(e.steps[k] ? stepBlock(e.steps[k]) : el('div'));
  }
  show(grid);
}

async function route() {
  ++routeSeq;
  clearTimeout(refreshTimer);
  episodeKeys = null;
  const hash = location.hash.slice(1) || '/';
  const [path, query] = hash.split('?');
  const params = new URLSearchParams(query || '');
  const parts = path.split('/').filter(Boolean).map(decodeURIComponent);
  try {
    if (parts.length === 0) await showRuns();
    else if (parts[0] === 'leaderboard') await showLeaderboard();
    else if (parts[0] === 'compare') await showCompare(params);
    else if (parts[0] === 'comparison') await showComparison(params);
    else if (parts[0] === 'run' && parts.length === 2) await showOverview(parts[1], params);
    else if (parts[0] === 'run' && parts[2] === 'episodes') await showEpisodes(parts[1], params);
    else if (parts[0] === 'run' && parts[2] === 'episode') {
      await showEpisode(parts[1], parts[3], params, parts[4] === 'step' ? Number(parts[5]) : null);
    }
    else show(el('p', {}, 'Nothing here: ' + hash));
  } catch (err) {
    if (err instanceof StaleRoute) return;
    show(el('p', {class: 'error'}, 'Error: ' + err.message));
  }
}

window.addEventListener('hashchange', route);
route();
