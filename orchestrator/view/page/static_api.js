// The viewer's JSON API answered from the files `mtg export` wrote, so an exported site works
// from file:// and offline (docs/view.md "Sharing a run"). A browser does not fetch() file://
// URLs, so each data file is a script calling mtgPut(its path, its value). Episode lists,
// search, sorting and neighbours are computed here from the run's rows exactly as the server's
// episode_query.cc does; a Chromium test compares the two.
'use strict';

(function () {
  const store = new Map();
  window.mtgPut = (file, value) => { store.set(file, value); };

  function load(file) {
    if (store.has(file)) return Promise.resolve(store.get(file));
    return new Promise((resolve, reject) => {
      const s = document.createElement('script');
      s.src = file;
      s.onload = () => (store.has(file) ? resolve(store.get(file)) : reject(new Error(file + ' holds no data')));
      s.onerror = () => reject(new Error('not in this export: ' + file));
      document.head.append(s);
    });
  }

  const SORT_FIELDS = ['episode', 'agent', 'level', 'scene', 'task', 'text', 'verdict', 'ip', 'stage', 'cause', 'steps'];
  const threeWay = (a, b) => (a < b ? -1 : b < a ? 1 : 0);
  const KEY = {
    episode: (r) => r.episode_id, agent: (r) => r.agent, level: (r) => r.level, scene: (r) => r.scene,
    task: (r) => r.task_id, text: (r) => r.task_text, verdict: (r) => (r.status !== 'scored' ? 0 : r.success ? 2 : 1),
    ip: (r) => r.ip, stage: (r) => r.stage, cause: (r) => r.cause, steps: (r) => r.steps,
  };

  function number(q, name) {
    const v = q.get(name);
    if (v === null || v === '') return null;
    if (!/^-?\d+$/.test(v)) throw new Error("query parameter '" + name + "' is not a number: " + v);
    return Number(v);
  }

  // ASCII lower case, as the server's std::tolower: the same needle finds the same rows.
  const lower = (t) => t.replace(/[A-Z]/g, (c) => c.toLowerCase());

  // episode_query.cc: filters, the case-insensitive search over task ids, texts and what the
  // agents said (each row's "said", written by the export), a stable
  // sort with ties in episode order.
  function select(rows, q) {
    const text = lower(q.get('q') || '');
    const level = number(q, 'level');
    const success = q.get('success');
    const cause = q.get('cause');
    const sort = q.get('sort') || 'episode';
    if (!SORT_FIELDS.includes(sort)) throw new Error("query parameter 'sort' must be one of " + SORT_FIELDS.join(', ') + ', not ' + sort);
    const desc = q.get('order') === 'desc';
    const out = rows.filter((r) => {
      for (const f of ['agent', 'scene', 'stage', 'status']) if (q.get(f) && r[f] !== q.get(f)) return false;
      if (q.get('task') && r.task_id !== q.get('task')) return false;
      if (level !== null && r.level !== level) return false;
      if (success !== null && success !== '' && r.success !== (success === '1' || success === 'true')) return false;
      if (cause) {
        const wanted = cause === 'success' ? '' : cause;
        if (r.cause !== wanted || (cause === 'success') !== r.success) return false;
      }
      return !text || lower(r.task_id).includes(text) || lower(r.task_text || '').includes(text) ||
        (r.said || '').includes(text);
    });
    const key = KEY[sort];
    return out.sort((a, b) => {
      const c = threeWay(key(a), key(b));
      if (c !== 0) return desc ? -c : c;
      return a.episode_id - b.episode_id;
    });
  }

  window.mtgStaticApi = async (path) => {
    const url = new URL(path, 'http://export.invalid');
    const parts = url.pathname.split('/').filter(Boolean).map(decodeURIComponent);  // api, runs, <run>, ...
    const q = url.searchParams;
    if (parts[1] === 'compare') {  // computed by the export for the choices the overview offers
      const files = await load('data/comparisons.js');
      const key = ['a', 'b', 'agent', 'baseline'].filter((k) => q.get(k)).map((k) => k + '=' + q.get(k)).join('&');
      if (!files[key]) throw new Error('this comparison is not in the export (mtg view compares any two): ' + key);
      return load(files[key]);
    }
    if (parts[1] === 'leaderboard') return load('data/leaderboard.js');
    const runs = await load('data/runs.js');
    if (parts.length === 2) return runs.map((r) => r.summary);
    const run = runs.find((r) => r.summary.name === parts[2]);
    if (!run) throw new Error("no run named '" + parts[2] + "'");
    const dir = 'data/' + run.dir + '/';
    if (parts.length === 3) return load(dir + 'run.js');
    if (parts[3] === 'report') {
      const i = run.agents.indexOf(q.get('agent'));
      if (i < 0) throw new Error("run " + run.summary.name + " has no episode of agent '" + q.get('agent') + "'");
      return load(dir + 'report-' + i + '.js');
    }
    if (parts[3] === 'sankey.svg') {
      const i = q.get('agent') ? run.agents.indexOf(q.get('agent')) : -1;
      return load(dir + (i < 0 ? 'sankey.js' : 'sankey-' + i + '.js'));
    }
    if (parts[3] === 'marks') {
      const all = await load(dir + 'marks.js');
      const episode = q.get('episode');
      if (!episode || Number(episode) < 0) return all;  // as the server: no valid episode, every mark
      return {marks: all.marks[episode] ? {[episode]: all.marks[episode]} : {},
        trail: all.trail.filter((e) => String(e.episode) === episode)};
    }
    if (parts[3] !== 'episodes') throw new Error('not in this export: ' + path);
    const rows = await load(dir + 'rows.js');
    if (parts.length === 4) {
      const selected = select(rows, q);
      const offset = number(q, 'offset') || 0;
      const limit = number(q, 'limit') === null ? 100 : number(q, 'limit');
      // The rows as the server sends them: "said" is for the search only.
      const page = selected.slice(offset, offset + limit).map(({said, ...row}) => row);
      return {total: selected.length, offset, rows: page};
    }
    const id = Number(parts[4]);
    if (parts[5] === 'neighbours') {
      const selected = select(rows, q);
      const k = selected.findIndex((r) => r.episode_id === id);
      if (k < 0) return {position: null, total: selected.length, previous: null, next: null};
      return {position: k, total: selected.length, previous: k > 0 ? selected[k - 1].episode_id : null,
        next: k + 1 < selected.length ? selected[k + 1].episode_id : null};
    }
    const file = await load(dir + 'episodes/' + id + '.js');
    const attempt = q.get('attempt') !== null ? q.get('attempt') : String(file.attempt);
    if (parts[5] === 'truth') {
      if (!file.truth[attempt]) throw new Error('no goal recorded for that episode');
      return file.truth[attempt];
    }
    if (!file.attempts[attempt]) throw new Error('episode ' + id + ' has no attempt ' + attempt + ' in this export');
    return file.attempts[attempt];
  };
})();
