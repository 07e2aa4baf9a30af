// The class as tiles, one per trainee's session, from each ClassStatus:
// device, depth, layer, force, peak, a force sparkline, late ticks, the
// latest event and the score. Click a tile to open that trainee's view.
import {drawPlot, History} from './sparkline.js';

export class TileBoard {
  constructor(root, onOpen) {
    this.root = root;
    this.onOpen = onOpen;
    this.tiles = new Map();  // session id -> { element, fields, history, events }
  }

  update(status) {
    const seen = new Set();
    for (const s of status.sessions) {
      seen.add(s.sessionId);
      const tile = this.tiles.get(s.sessionId) || this.create(s.sessionId);
      tile.history.add(s.simTimeS, s.forceN);
      tile.events += s.events.length;
      if (s.events.length) tile.lastEvent = s.events[s.events.length - 1].kind;
      const f = tile.fields;
      f.trainee.textContent = s.trainee || s.sessionId;
      f.scene.textContent = s.scene;
      f.device.textContent = s.deviceStreaming ? 'device on' : 'no device';
      f.device.dataset.on = s.deviceStreaming;
      f.depth.textContent = `${(s.tipDepthM * 1e3).toFixed(1)} mm`;
      f.layer.textContent = s.layerName || s.contactState;
      f.force.textContent = `${s.forceN.toFixed(2)} N`;
      f.peak.textContent = `peak ${s.peakToolForceN.toFixed(2)} N`;
      f.late.textContent = `${s.lateTicks} late`;
      f.events.textContent = `${tile.events} events${tile.lastEvent ? ` · ${tile.lastEvent}` : ''}`;
      f.score.textContent = s.experts > 0 ? `score ${s.score.toFixed(1)}` : '';
      f.paused.hidden = !s.paused;
      tile.element.dataset.ticks = String(s.ticks);
      drawPlot(f.spark, tile.history.points);
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
    const tile = {element, fields, history: new History(100), events: 0, lastEvent: ''};
    this.tiles.set(id, tile);
    const after = [...this.tiles.keys()].sort();
    this.root.append(element);
    for (const key of after) this.root.append(this.tiles.get(key).element);  // sorted by id
    return tile;
  }
}
