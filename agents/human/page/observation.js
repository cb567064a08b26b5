// Draws one observation as the agent received it: images, situation text, feedback and the
// offered actions. Shared by the viewer (read-only, the chosen key marked) and the play page
// (actions are buttons). No framework: plain DOM.
'use strict';

function el(tag, attrs, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (k === 'class') node.className = v;
    else if (k.startsWith('on')) node.addEventListener(k.slice(2), v);
    else node.setAttribute(k, v);
  }
  for (const c of children.flat()) {
    if (c === null || c === undefined || c === false) continue;
    node.append(c instanceof Node ? c : document.createTextNode(String(c)));
  }
  return node;
}

const ROLE_WORDS = {
  view: 'view', view_marked: 'view, marked', view_zoom: 'crowded part, zoomed', item: 'in your hand',
  topdown: 'top-down map', topdown_marked: 'top-down map, marked', focus: 'close-up',
};

// obs: {text, hint, actions[{key, description}], images[{role, url, width, height}]}
// opts: {onKey(key)} for buttons, or {chosen: key} for a read-only list; {eager: true} loads every
// image at once (the audit page: a person compares observations far down the page).
function renderObservation(obs, opts) {
  opts = opts || {};
  const images = el('div', {class: 'obs-images'});
  for (const img of obs.images || []) {
    if (!img.url) {
      images.append(el('figure', {}, el('figcaption', {}, (ROLE_WORDS[img.role] || img.role) + ' (not recorded)')));
      continue;
    }
    images.append(el('figure', {},
      el('a', {href: img.url, target: '_blank'}, el('img', {src: img.url, alt: img.role, loading: opts.eager ? 'eager' : 'lazy', width: img.width, height: img.height})),
      el('figcaption', {}, el('b', {}, ROLE_WORDS[img.role] || img.role), img.caption ? ' ' + img.caption : '')));
  }
  const actions = el('div', {class: opts.onKey ? 'actions' : 'actions readonly'});
  for (const a of obs.actions || []) {
    if (opts.onKey) {
      actions.append(el('button', {'data-key': a.key, title: a.description, onclick: () => opts.onKey(a.key)},
        el('b', {}, a.key), a.description));
    } else {
      actions.append(el('span', {class: a.key === opts.chosen ? 'chosen' : '', title: a.description},
        a.key + ' ' + a.description));
    }
  }
  const count = 'Offered actions (' + (obs.actions || []).length + ')';
  // Read-only lists are long (60+ platforms): folded, with the chosen key in the summary.
  const list = opts.onKey ? [el('div', {class: 'muted'}, count + ':'), actions]
    : [el('details', {}, el('summary', {class: 'muted'}, count + (opts.chosen ? ', chosen: ' + opts.chosen : '')), actions)];
  return el('div', {class: 'observation'},
    images,
    opts.told && obs.task_text ? el('div', {class: 'obs-task'}, 'Task as told: ' + obs.task_text) : null,
    obs.hint ? el('div', {class: 'obs-hint'}, 'Feedback: ' + obs.hint) : null,
    el('pre', {class: 'obs-text'}, obs.text || ''),
    ...list);
}
