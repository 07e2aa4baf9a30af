// The console's one WebSocket to the server (/ws on the page's own host,
// wss: under https:). Speaks hapsim.v1.ConsoleRequest / ConsoleEvent,
// binary protobuf. Gives the token once per connection in a hello (never in
// a URL), and after a lost connection reconnects and asks again for what
// was open (the class view, the trainee view), so a server restart costs a
// few seconds, not a reload. A refusal (bad token) is final.
import {create, fromBinary, toBinary} from '@bufbuild/protobuf';
import {ConsoleEventSchema, ConsoleRequestSchema} from 'hapsim-proto/console_pb.js';

export class ConsoleConnection {
  // handlers: onEvent(event), onState(state, detail) with state in
  // connecting | open | lost | refused.
  constructor(token, handlers) {
    this.token = token;
    this.handlers = handlers;
    this.nextCallId = 1;
    this.pending = new Map();  // call id -> resolve
    this.watch = null;         // the WatchClassRequest to restore after a reconnect
    this.view = null;          // the SubscribeRequest likewise
    this.refused = false;
    this.retryMs = 500;
    this.handlingMs = 0;
    this.messages = 0;
    this.losses = 0;    // connections lost so far; with welcomes, lets a test see a reconnect however fast it was
    this.welcomes = 0;  // connections the server accepted so far
    this.open();
  }

  open() {
    const scheme = location.protocol === 'https:' ? 'wss:' : 'ws:';
    this.ws = new WebSocket(`${scheme}//${location.host}/ws`);
    this.ws.binaryType = 'arraybuffer';
    this.handlers.onState('connecting');
    this.ws.onopen = () => {
      this.retryMs = 500;
      this.send({case: 'hello', value: {token: this.token}});
    };
    this.ws.onmessage = (m) => this.receive(new Uint8Array(m.data));
    this.ws.onclose = () => {
      for (const resolve of this.pending.values()) resolve({code: 14, message: 'connection lost'});
      this.pending.clear();
      if (this.refused) return;
      this.losses++;
      this.handlers.onState('lost');
      setTimeout(() => this.open(), this.retryMs);
      this.retryMs = Math.min(this.retryMs * 2, 4000);
    };
  }

  receive(bytes) {
    const start = performance.now();
    try {
      this.handle(bytes);
    } finally {
      this.handlingMs += performance.now() - start;  // the page's own cost per message, for the lag benchmark
      this.messages++;
    }
  }

  handle(bytes) {
    let event;
    try {
      event = fromBinary(ConsoleEventSchema, bytes);
    } catch (e) {
      console.warn('not a ConsoleEvent', e);
      return;
    }
    const {case: kind, value} = event.event;
    if (kind === 'welcome') {
      this.welcomes++;
      this.handlers.onState('open', value);
      if (this.watch) this.send({case: 'watchClass', value: this.watch});
      if (this.view) this.send({case: 'openView', value: this.view});
    } else if (kind === 'refused') {
      this.refused = true;
      this.handlers.onState('refused', value);
    } else if (kind === 'reply') {
      const resolve = this.pending.get(value.id);
      this.pending.delete(value.id);
      if (resolve) resolve(value);
    }
    this.handlers.onEvent(event.event);
  }

  send(request) {
    if (this.ws.readyState !== WebSocket.OPEN) return false;
    this.ws.send(toBinary(ConsoleRequestSchema, create(ConsoleRequestSchema, {request})));
    return true;
  }

  watchClass(className, rateHz) {
    this.watch = {className, rateHz};
    this.send({case: 'watchClass', value: this.watch});
  }

  openView(sessionId) {
    this.view = {sessionId, maxRateHz: 60, viewerName: 'browser console', ackWindow: 2};
    this.send({case: 'openView', value: this.view});
  }

  closeView() {
    this.view = null;
    this.send({case: 'closeView', value: {}});
  }

  statusShown(seq) {
    this.send({case: 'statusAck', value: {seq}});
  }

  ack(appliedSeq, heldUs) {
    this.send({case: 'ack', value: {appliedSeq, heldUs: BigInt(Math.max(0, Math.round(heldUs)))}});
  }

  // One SessionService call: method is the ConsoleCall field ("pauseSession",
  // "getTrials", ...). Resolves to the ConsoleReply ({code, message, response}).
  call(method, request) {
    const id = this.nextCallId++;
    return new Promise((resolve) => {
      this.pending.set(id, resolve);
      if (!this.send({case: 'call', value: {id, call: {case: method, value: request}}})) {
        this.pending.delete(id);
        resolve({code: 14, message: 'not connected'});
      }
    });
  }
}
