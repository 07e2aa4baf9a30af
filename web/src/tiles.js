// The class as tiles, one per trainee's session, from each ClassStatus:
// device, depth, layer, force, peak, a force sparkline, late ticks, the
// latest event and the score. Click a tile to open that trainee's view.
//
// A slow tab must not fall behind: a status is drawn on the next animation
// frame, a newer one arriving before that replaces it, and onShown(seq)
// then tells the server, which sends the next status only after that
// (newest wins). Only text that changed is written, and only the tiles on
// screen redraw their sparklines.
import {drawPlot, History} from './sparkline.js';

const setText = (element, text) => {
  if (element.textContent !== text) element.textContent = text;
};

export class TileBoard {
  constructor(root, onOpen, onShown) {
    this.root = root;
    this.onOpen = onOpen;
    this.onShown = onShown;
    this.tiles = new Map();  // session id -> { element, fields, history, lastEvent, onScreen }
    this.waiting = null;     // the newest status not yet drawn
    this.onScreen = new IntersectionObserver((entries) => {
      for (const e of entries) {
        const tile = this.tiles.get(e.target.dataset.session);
        if (tile) tile.onScreen = e.isIntersecting;
      }
    });
  }

  // A ClassStatus arrived: drawn on the next animation frame.
  update(status) {
    const first = this.waiting === null;
    this.waiting = status;
    if (first) requestAnimationFrame(() => this.draw());
  }

  draw() {
    const status = this.waiting;
    this.waiting = null;
    if (status === null) return;  // dropped by markStale
    this.show(status);
    this.onShown(status.seq);
  }

  // The link is lost: what the tiles show is from before, so they say so
  // (dimmed) until the server's next status for each.
  markStale() {
    this.waiting = null;
    for (const tile of this.tiles.values()) tile.element.dataset.stale = 'true';
  }

  show(status) {
    const seen = new Set();
    for (const s of status.sessions) {
      seen.add(s.sessionId);
      const tile = this.tiles.get(s.sessionId) || this.create(s.sessionId);
      tile.history.add(s.simTimeS, s.forceN);
      if (s.events.length) tile.lastEvent = s.events[s.events.length - 1].kind;
      const f = tile.fields;
      setText(f.trainee, s.trainee || s.sessionId);
      setText(f.scene, s.scene);
      setText(f.device, s.deviceStreaming ? 'device on' : 'no device');
      f.device.dataset.on = s.deviceStreaming;
      setText(f.depth, `${(s.tipDepthM * 1e3).toFixed(1)} mm`);
      setText(f.layer, s.layerName || s.contactState);
      setText(f.force, `${s.forceN.toFixed(2)} N`);
      setText(f.peak, `peak ${s.peakToolForceN.toFixed(2)} N`);
      setText(f.late, `${s.lateTicks} late`);
      setText(f.events, `${s.eventsTotal} events${tile.lastEvent ? ` · ${tile.lastEvent}` : ''}`);
      setText(f.score, s.experts > 0 ? `score ${s.score.toFixed(1)}` : '');
      if (f.paused.hidden === s.paused) f.paused.hidden = !s.paused;
      tile.element.dataset.ticks = String(s.ticks);
      tile.element.dataset.stale = 'false';
      tile.element.dataset.simTime = String(s.simTimeS);  // stands still while paused
      if (tile.onScreen) drawPlot(f.spark, tile.history.points);
    }
    for (const id of status.missingSessions) seen.add(id);
    for (const [id, tile] of this.tiles)
      tile.element.dataset.missing = String(!seen.has(id) || status.missingSessions.includes(id));
  }

  create(id) {
    const element = document.createElement('button');
    element.className = 'tile';
    element.dataset.session = id;
    const fields = {};
    for (const name of ['trainee', 'scene', 'device', 'depth', 'layer', 'force', 'peak', 'late', 'events', 'score']) {
      fields[name] = document.createElement('span');
      fields[name].className = name;
      element.append(fields[name]);
    }
    fields.paused = Object.assign(document.createElement('span'), {className: 'paused', textContent: 'paused'});
    fields.spark = Object.assign(document.createElement('canvas'), {className: 'spark', width: 160, height: 36});
    element.append(fields.paused, fields.spark);
    element.addEventListener('click', () => this.onOpen(id));
    const tile = {element, fields, history: new History(100), lastEvent: '', onScreen: true};
    this.tiles.set(id, tile);
    this.onScreen.observe(element);
    const after = [...this.tiles.keys()].sort();
    this.root.append(element);
    for (const key of after) this.root.append(this.tiles.get(key).element);  // sorted by id
    return tile;
  }
}
