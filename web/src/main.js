// The class console page: log in with a token, watch the class as tiles
// (one per trainee), open a trainee's 3D view with live force plots, and
// run the class as the token's role allows. Everything the page shows comes
// over one WebSocket (connection.js); every action is checked again by the
// server's access policy.
import {ConsoleConnection} from './connection.js';
import {MeshCache} from './mesh_cache.js';
import {drawPlot, History} from './sparkline.js';
import {TileBoard} from './tiles.js';
import {fillTrialsTable} from './trials_table.js';
import {View3D} from './view3d.js';

const $ = (id) => document.getElementById(id);
const GRPC_NAMES = {
  0: 'OK',
  3: 'invalid argument',
  5: 'not found',
  7: 'permission denied',
  14: 'unavailable',
  16: 'unauthenticated'
};

class ConsolePage {
  constructor() {
    this.welcome = null;
    this.openSession = null;
    this.cache = new MeshCache();
    this.view = null;
    this.forceTime = new History(600);
    this.forceDepth = new History(600);
    this.framesApplied = 0;
    this.plotsDrawnAt = -1e9;
    this.newEvents = [];  // events of frames applied since the last drawing
    // The newest drawings: [drawn at, the frame's server send time (both ms
    // since the Unix epoch), drawing ms]: how far the view lags.
    this.frameLog = [];

    this.tiles = new TileBoard($('tiles'), (id) => this.open(id), (seq) => this.connection?.statusShown(seq));
    $('login').addEventListener('submit', (e) => {
      e.preventDefault();
      this.connect($('token').value, $('class-name').value.trim());
    });
    $('close-detail').addEventListener('click', () => this.close());
    for (const b of document.querySelectorAll('#controls button[data-action]')) {
      b.addEventListener('click', () => this.control(b.dataset.action));
    }
    $('trials').addEventListener('click', () => this.showTrials());
    $('close-trials').addEventListener('click', () => ($('trials-panel').hidden = true));
    $('push').addEventListener('click', () => this.pushScenario());
  }

  connect(token, className) {
    if (this.connection) return;
    $('login-error').textContent = '';
    this.className = className;
    this.connection = new ConsoleConnection(token, {
      onState: (state, detail) => this.onState(state, detail),
      onEvent: (event) => this.onEvent(event),
    });
  }

  onState(state, detail) {
    $('link-state').textContent = state;
    $('link-state').dataset.state = state;
    if (state === 'open') {
      this.welcome = detail;
      $('token').value = '';  // the connection keeps it; the page need not
      $('login').hidden = true;
      $('console').hidden = false;
      const role = detail.role || 'development mode';
      $('who').textContent = detail.name ? `${detail.name} (${role}, class ${detail.className})` : role;
      document.body.dataset.role = detail.role || 'any';
      this.applyRole(detail.role);
      if (!this.watching) {
        this.connection.watchClass(this.className || detail.className, 10);
        this.watching = true;
      }
    } else if (state === 'lost') {
      this.tiles.markStale();
    } else if (state === 'refused') {
      this.connection = null;
      $('login').hidden = false;
      $('console').hidden = true;
      $('login-error').textContent = `Refused: ${detail.message}`;
    }
  }

  // What the role may do, as buttons: the server checks every call anyway.
  applyRole(role) {
    const control = role === '' || role === 'instructor';
    for (const b of document.querySelectorAll('#controls button[data-action]')) {
      b.disabled = !control;
      b.title = control ? '' : `a ${role} cannot ${b.dataset.action} a session`;
    }
    $('class-actions').hidden = !(role === '' || role === 'instructor' || role === 'observer');
    $('push').disabled = !(role === '' || role === 'instructor');
  }

  onEvent(event) {
    if (event.case === 'classStatus') {
      this.tiles.update(event.value);  // acknowledged once drawn
    } else if (event.case === 'frame') {
      this.onFrame(event.value);
    } else if (event.case === 'ended') {
      this.say(`${event.value.stream} view ended: ${
          event.value.message || GRPC_NAMES[event.value.code] || event.value.code}`);
      if (event.value.stream === 'class') this.watching = false;
    }
  }

  open(sessionId) {
    this.openSession = sessionId;
    this.cache = new MeshCache();
    this.newestFrame = null;
    this.newEvents = [];
    this.forceTime.clear();
    this.forceDepth.clear();
    $('detail').hidden = false;
    $('detail-title').textContent = sessionId;
    if (!this.view && !this.noWebGl) {
      try {
        this.view = new View3D($('view3d'));
      } catch (e) {  // no WebGL here (switched off, or no driver): tiles, plots and controls still work
        this.noWebGl = true;
        $('view3d').hidden = true;
        this.say(`no 3D view in this browser (${e.message}); the plots and controls work`);
      }
    }
    if (this.view) this.view.reset();
    this.connection.openView(sessionId);
  }

  close() {
    this.openSession = null;
    $('detail').hidden = true;
    this.connection.closeView();
  }

  // A frame is applied and acknowledged at once (cheap: a delta is a few
  // hundred bytes); drawing waits for the next animation frame and shows
  // the newest state, so a slow tab draws less often but never falls behind.
  onFrame(frame) {
    const received = performance.now();
    const why = this.cache.apply(frame);
    if (why) {  // out of step (a lost frame): a new subscription starts with a keyframe
      console.warn('frame not applied:', why);
      this.cache = new MeshCache();
      this.connection.openView(this.openSession);
      return;
    }
    this.connection.ack(frame.seq, performance.now() - received);
    this.framesApplied++;
    this.forceTime.add(frame.simTimeS, frame.peakForceN);
    this.forceDepth.add(frame.tipDepthM * 1e3, frame.peakForceN);
    this.newestFrame = frame;
    this.newEvents.push(...frame.events);
    if (!this.drawPending) {
      this.drawPending = true;
      requestAnimationFrame(() => this.draw());
    }
  }

  draw() {
    this.drawPending = false;
    const frame = this.newestFrame;
    if (!frame || !this.openSession) return;
    const start = performance.now();
    if (this.view) this.view.update(this.cache, frame.tool, this.newEvents);
    this.newEvents = [];
    const t = frame.simTimeS;
    if (start - this.plotsDrawnAt < 100) {  // plots and text at 10 Hz: enough to read, cheap on a slow tab
      this.logDrawing(start, frame);
      return;
    }
    this.plotsDrawnAt = start;
    drawPlot($('plot-time'), this.forceTime.points, {xLabel: 'time [s]', yLabel: 'peak force [N]'});
    drawPlot(
        $('plot-depth'), this.forceDepth.points,
        {xLabel: 'depth [mm]', yLabel: 'force [N]', color: '#36c', scatter: true});
    const layer = this.cache.layerNames[frame.currentLayer] || '—';
    $('detail-status').textContent =
        `t ${t.toFixed(2)} s · depth ${(frame.tipDepthM * 1e3).toFixed(2)} mm · layer ${layer} · ` +
        `force ${frame.peakForceN.toFixed(3)} N · ${frame.tool ? frame.tool.contactState : 'no tool'}` +
        (frame.paused ? ' · paused' : '');
    this.logDrawing(start, frame);
  }

  logDrawing(start, frame) {
    const now = performance.now();
    this.frameLog.push([performance.timeOrigin + now, frame.sentUnixS * 1e3, now - start]);
    if (this.frameLog.length > 4096) this.frameLog.splice(0, 2048);
  }

  async control(action) {
    if (!this.openSession) return;
    const method = {pause: 'pauseSession', resume: 'resumeSession', reset: 'resetSession'}[action];
    const reply = await this.connection.call(method, {sessionId: this.openSession});
    this.say(
        reply.code === 0 ? `${action}: done` :
                           `${action} refused: ${reply.message} (${GRPC_NAMES[reply.code] || reply.code})`);
    return reply;
  }

  // The class's trials as a table, with the same CSV to download.
  async showTrials() {
    const reply = await this.connection.call('getTrials', {className: this.className || this.welcome.className});
    if (reply.code !== 0) return this.say(`trials refused: ${reply.message}`);
    const csv = reply.response.value.csv;
    const rows = fillTrialsTable($('trials-table'), csv);
    const link = $('trials-csv');
    if (link.href) URL.revokeObjectURL(link.href);
    link.href = URL.createObjectURL(new Blob([csv], {type: 'text/csv'}));
    $('trials-panel').hidden = false;
    this.say(`${rows} trials`);
    return reply;
  }

  async pushScenario() {
    const scene = $('push-scene').value.trim();
    if (!scene) return;
    const reply = await this.connection.call(
        'pushScenario', {className: this.className || this.welcome.className, scene, params: {}});
    this.say(reply.code === 0 ? `scenario ${scene} pushed` : `push refused: ${reply.message}`);
  }

  say(text) {
    $('message').textContent = text;
  }
}

window.hapsim = new ConsolePage();
