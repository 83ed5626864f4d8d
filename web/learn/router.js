// Teaching views and the paper's demos (#learn/..., #demo/...): a small hash router beside the
// editor. main.js asks learnRoute() at start: on a learn URL it calls startLearn() instead of the
// editor. Each view is a module of its own, loaded when its URL is opened; a view gets the API
// (lib/api.mjs through ../mrvol.js) and a layout to draw into, and returns { dispose, debug }.
import { loadMrvol } from '../mrvol.js';
import './learn.css';
import { NAV_TITLES, titleControls } from './titles.js';

export const VIEWS = [
  { route: 'learn/levels', title: 'Levels', load: () => import('./levels.js') },
  { route: 'demo/ball', title: 'Bouncing ball', load: () => import('./ball.js') },
  { route: 'demo/skinning', title: 'Skinning', load: () => import('./skinning.js') },
  { route: 'learn/tensor', title: 'Volume tensor', load: () => import('./tensor.js') },
  { route: 'demo/bunny', title: 'Pulling ears', load: () => import('./bunny.js') },
  { route: 'demo/balance', title: 'Keeping balance', load: () => import('./balance.js') },
  { route: 'learn/lifting', title: 'Lifting', load: () => import('./lifting.js') },
];

/** The learn route of a hash ('#learn/levels' -> 'learn/levels'), or null for the editor. */
export function learnRoute(hash = location.hash) {
  const route = hash.replace(/^#/, '').split('?')[0];
  return /^(learn|demo)\//.test(route) ? route : null;
}

const state = { mrvol: null, current: null, generation: 0, layout: null };

function el(tag, attributes = {}, ...children) {
  const element = document.createElement(tag);
  for (const [k, v] of Object.entries(attributes)) {
    if (k === 'testid') element.dataset.testid = v;
    else if (k === 'text') element.textContent = v;
    else element.setAttribute(k, v);
  }
  element.append(...children);
  return element;
}

function buildLayout() {
  document.body.classList.add('learn-mode');
  const nav = el('nav', { class: 'learn-nav', testid: 'learn-nav' });
  nav.append(el('a', { href: './', class: 'learn-editor-link', text: '← editor', title: 'Back to the editor (with its model and edits)' }));
  for (const view of VIEWS)
    nav.append(el('a', { href: `#${view.route}`, 'data-route': view.route, testid: `nav-${view.route.replace('/', '-')}`, text: view.title,
      title: NAV_TITLES[view.route] ?? view.title }));
  const stage = el('div', { class: 'learn-stage', testid: 'learn-stage' });
  const text = el('div', { class: 'learn-text', testid: 'learn-text' });
  const controls = el('div', { class: 'learn-controls', testid: 'learn-controls' });
  const readouts = el('div', { class: 'learn-readouts', testid: 'learn-readouts' });
  const aside = el('aside', { class: 'learn-aside' }, text, controls, readouts);
  const bottom = el('div', { class: 'learn-bottom', testid: 'learn-bottom' });
  const main = el('main', { class: 'learn-main' }, stage, bottom);
  const status = el('div', { class: 'learn-status', testid: 'learn-status' });
  const root = el('div', { id: 'learn', testid: 'learn' }, nav, el('div', { class: 'learn-body' }, main, aside), status);
  document.body.append(root);
  return { root, nav, stage, text, controls, readouts, bottom, status };
}

function clearLayout(layout) {
  for (const part of [layout.stage, layout.text, layout.controls, layout.readouts, layout.bottom]) part.replaceChildren();
  layout.bottom.hidden = true;
  layout.status.textContent = '';
  layout.status.classList.remove('learn-error');
  layout.root.dataset.ready = 'false';
}

async function show(route) {
  const generation = ++state.generation;
  const layout = state.layout;
  state.current?.dispose?.();
  state.current = null;
  clearLayout(layout);
  for (const a of layout.nav.querySelectorAll('a[data-route]')) a.classList.toggle('active', a.dataset.route === route);
  const view = VIEWS.find((v) => v.route === route);
  layout.root.dataset.view = route;
  if (!view) {
    layout.text.append(el('p', { text: `There is no view '${route}'. Pick one above.` }));
    layout.root.dataset.ready = 'true';
    return;
  }
  document.title = `mrvol: ${view.title}`;
  try {
    const module = await view.load();
    if (generation !== state.generation) return;
    const instance = await module.mount({ mrvol: state.mrvol, layout, el, stale: () => generation !== state.generation });
    if (generation !== state.generation) {
      instance?.dispose?.();
      return;
    }
    state.current = instance;
    layout.root.dataset.ready = 'true';
  } catch (e) {
    if (generation !== state.generation) return;
    layout.status.textContent = `This view failed: ${e.message}`;
    layout.status.classList.add('learn-error');
    layout.root.dataset.ready = 'error';
    console.error(e);
  }
}

/** Runs the teaching views instead of the editor. */
export async function startLearn() {
  state.layout = buildLayout();
  // controls a view makes, now or later (the level buttons of #learn/levels), get their tooltips
  const { root } = state.layout;
  new MutationObserver(() => titleControls(root)).observe(root, { subtree: true, childList: true });
  Object.defineProperty(window, 'mrvolLearn', {
    value: Object.freeze({
      route: () => learnRoute(),
      // Ready for the route in the address bar, not a view it is about to leave (hashchange comes later).
      ready: () => state.layout.root.dataset.ready === 'true' && state.layout.root.dataset.view === learnRoute(),
      state: () => state.current?.debug?.() ?? null,
      act: (name, ...args) => state.current?.actions?.[name]?.(...args),
    }),
  });
  try {
    state.mrvol = await loadMrvol();
  } catch (e) {
    state.layout.status.textContent = `The WebAssembly core could not be loaded: ${e.message}`;
    return;
  }
  window.addEventListener('hashchange', () => {
    const route = learnRoute();
    if (route) show(route);
    else location.reload(); // back to the editor
  });
  show(learnRoute());
}

/** In the editor: a learn URL typed in the address bar reloads into the teaching views. */
export function watchForLearnRoutes() {
  window.addEventListener('hashchange', () => {
    if (learnRoute()) location.reload();
  });
}
