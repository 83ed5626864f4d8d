// The free set in the panel and under the pointer: the mode and the painted region and parts as
// settings (stored with the session), paint strokes over handles, the handles' colours, the pointer
// tool's notice. The session applies them (lib/three/session.mjs keeps only the cage's vertices).
import { FREE_SET_MODES, MAX_PARTS } from '../lib/three/session.mjs';
import { TOOLS } from './panel.js';
import { notice, noticeText } from './readouts.js';

const PAINT_COLOR = '#bf3989';
const PART_COLORS = ['#cf222e', '#8250df', '#0e8a94', '#9a6700', '#bf3989', '#57606a', '#24292f', '#7d8a00'];
const TOOL_NAMES = Object.values(TOOLS);

export class FreeSetTools {
  #stroke = null; // the paint stroke going on: { add }

  /** settings: { freeSet, tool, part, painted, parts } (painted and parts are replaced, never mutated). */
  constructor({ session, viewer, panel, settings, defaults }) {
    Object.assign(this, { session, viewer, panel, settings, defaults });
    session.addEventListener('change', ({ detail }) => {
      if (detail.reason === 'free-set') this.showMarks();
    });
  }

  /** Hands the settings' free set to the session. */
  apply() {
    const { settings, session } = this;
    if (!session.editor) return;
    session.setFreeSet({ mode: settings.freeSet, painted: settings.painted, parts: settings.parts });
  }

  /** After a new cage: the settings keep only its vertices; the panel shows the mode's controls. */
  keepCageMarks() {
    const { settings, session } = this;
    // A quad editor may take fewer free sets (session.freeSetModes): the panel offers those only.
    const modes = session.freeSetModes ?? FREE_SET_MODES;
    if (!TOOL_NAMES.includes(settings.tool) || (settings.tool === 'paint' && !modes.includes('painted')) ||
        (settings.tool === 'assign' && !modes.includes('parts'))) settings.tool = this.defaults.tool;
    if (!modes.includes(settings.freeSet)) settings.freeSet = this.defaults.freeSet;
    this.panel.setFreeSets?.(modes);
    this.apply();
    Object.assign(settings, { painted: session.freeSet.painted, parts: session.freeSet.parts });
    this.panel.showModeControls();
    this.toolNotice();
  }

  /** Painted handles (paint tool or painted free set) or the parts' colours (assign tool or parts). */
  showMarks() {
    const { tool, freeSet, painted, parts } = this.settings;
    const cageIndex = this.session.cageIndex;
    if (!cageIndex) return;
    const marks = new Map();
    const showParts = tool === 'assign' || (tool !== 'paint' && freeSet === 'parts');
    const showPainted = tool === 'paint' || (tool !== 'assign' && freeSet === 'painted');
    if (showParts) parts.forEach((list, p) => list.forEach((v) => marks.set(cageIndex.get(v), PART_COLORS[p % PART_COLORS.length])));
    else if (showPainted) for (const v of painted) marks.set(cageIndex.get(v), PAINT_COLOR);
    this.viewer.setMarks(marks);
  }

  toolNotice() {
    const { tool } = this.settings;
    const text = tool === 'paint' ? 'Painting: click or drag over handles to add them to the free set or take them out.'
      : tool === 'assign' ? 'Assigning: click or drag over handles to put them in the chosen part or take them out.' : '';
    if (text || /^(Painting|Assigning):/.test(noticeText())) notice(text);
  }

  /** True while presses paint handles instead of dragging them. */
  get painting() { return this.settings.tool !== 'drag'; }

  /** A paint stroke passes over handle `index` (the first decides: add or remove). */
  paint(index, first) {
    const s = this.settings;
    const vertex = this.session.cageVertices[index];
    if (s.tool === 'paint') {
      const painted = new Set(s.painted);
      if (first || !this.#stroke) this.#stroke = { add: !painted.has(vertex) };
      if (this.#stroke.add) painted.add(vertex);
      else painted.delete(vertex);
      s.painted = [...painted];
    } else {
      const p = Math.min(MAX_PARTS, Math.max(1, Math.round(s.part))) - 1;
      if (first || !this.#stroke) this.#stroke = { add: !s.parts[p].includes(vertex) };
      s.parts = s.parts.map((list, q) => (this.#stroke.add || q === p ? list.filter((v) => v !== vertex) : list));
      if (this.#stroke.add) s.parts[p] = [...s.parts[p], vertex];
    }
    this.apply();
  }

  endStroke() {
    this.#stroke = null;
  }

  /** The panel's mode changed: the pointer follows (painting the region, assigning parts). */
  changeMode() {
    const mode = this.settings.freeSet;
    this.settings.tool = mode === 'painted' ? 'paint' : mode === 'parts' ? 'assign' : 'drag';
    this.panel.update();
    this.panel.showModeControls();
    this.toolNotice();
    this.apply();
  }

  changeTool() {
    this.panel.showModeControls();
    this.toolNotice();
    if (this.session.editor) this.showMarks();
  }

  clearPainted() {
    this.settings.painted = [];
    this.apply();
  }

  clearParts() {
    this.settings.parts = Array.from({ length: MAX_PARTS }, () => []);
    this.apply();
  }
}
