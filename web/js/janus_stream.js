// SPDX-License-Identifier: LGPL-2.1-or-later
// A broadcast through the Janus WebRTC server: its WebSocket API (create,
// attach to the streaming plugin, watch the mountpoint with its pin, answer
// the offer, start), with the viewer link's token on every request, the
// video, and the "frames" data channel that announces parameter versions
// (and, for a pool, the surface each frame shows).

import { watchIce } from './ice_watch.js';

const KEEPALIVE_MS = 25000;  // Janus ends a session silent for 60 s
const NO_SUCH_MOUNTPOINT = 455;  // the streaming plugin's error code

export class JanusStream {
  constructor({ url, mountpoint, pin, token }, video, { onState, onVersion, onParams, onReceiver, onFrame }) {
    Object.assign(this, { url, mountpoint, pin, token, video, onState, onVersion, onParams, onReceiver, onFrame });
    this.pending = new Map();  // transaction -> { resolve, reject }
    this.next = 0;
    this.closed = false;
  }

  async start() {
    this.socket = new WebSocket(this.url, 'janus-protocol');
    this.socket.onmessage = ({ data }) => this.onMessage(JSON.parse(data));
    this.socket.onclose = () => this.fail('the connection to the broadcast server closed');
    await new Promise((resolve, reject) => {
      this.socket.onopen = resolve;
      this.socket.onerror = () => reject(Object.assign(new Error('the broadcast server does not answer'), { transient: true }));
    });
    this.session = (await this.request({ janus: 'create' })).data.id;
    this.keepalive = setInterval(() => this.send({ janus: 'keepalive', session_id: this.session }), KEEPALIVE_MS);
    this.handle = (await this.request({ janus: 'attach', session_id: this.session,
                                       plugin: 'janus.plugin.streaming' })).data.id;
    this.pc = new RTCPeerConnection({ iceServers: [] });
    this.pc.ontrack = (event) => {
      if ('jitterBufferTarget' in event.receiver) event.receiver.jitterBufferTarget = 0;
      this.video.srcObject = event.streams[0] ?? new MediaStream([event.track]);
      this.video.play().catch(() => {});
    };
    this.pc.ondatachannel = ({ channel }) => this.listen(channel);
    this.pc.onicecandidate = ({ candidate }) => {
      this.send({ janus: 'trickle', session_id: this.session, handle_id: this.handle,
                  candidate: candidate ? candidate.toJSON() : { completed: true } });
    };
    this.ice = watchIce(this.pc, { onLive: () => this.onState('live'), onFail: (why) => this.fail(why) });
    const watched = await this.message({ request: 'watch', id: this.mountpoint, pin: this.pin });
    if (!watched.jsep) {
      const refusal = watched.plugindata?.data ?? {};
      // 455, no such mountpoint: after a restart of Janus, until the server
      // has made it again; anything else (a pin, a token) stays refused.
      throw Object.assign(new Error(refusal.error ?? 'the broadcast refused this link'),
                          { transient: refusal.error_code === NO_SUCH_MOUNTPOINT });
    }
    await this.pc.setRemoteDescription(watched.jsep);
    // Janus relays the mountpoint's data once the page has a channel of
    // its own (which sets up the SCTP association); it may answer on it.
    if (watched.jsep.sdp.includes('m=application')) this.listen(this.pc.createDataChannel('JanusDataChannel'));
    const answer = await this.pc.createAnswer();
    await this.pc.setLocalDescription(answer);
    await this.message({ request: 'start' }, { type: answer.type, sdp: answer.sdp });
    this.ice.arm();
  }

  // Frame messages: {"rtp_timestamp", "version", "level"} of the newest
  // picture sent (with "water" for a pool), also passed whole to onFrame;
  // {"params", "version"}: what places the room (screen, light, the
  // object's pose, a pool's size, the picture's size and the screen's tile
  // of it), and {"receiver", "version"}: each receiver with its tile, on
  // each change and each second.
  listen(channel) {
    channel.binaryType = 'arraybuffer';
    channel.onmessage = ({ data }) => {
      const message = JSON.parse(typeof data === 'string' ? data : new TextDecoder().decode(data));
      if (message.params) this.onParams?.(message.params, message.version);
      else if (message.receiver) this.onReceiver?.(message.receiver, message.version);
      else {
        this.onVersion(message.version, message.level);
        this.onFrame?.(message);
      }
    };
  }

  send(message) {
    if (this.socket?.readyState === WebSocket.OPEN) {
      this.socket.send(JSON.stringify({ ...message, token: this.token, transaction: `t${++this.next}` }));
    }
    return `t${this.next}`;
  }

  // A request's answer: "success", or for a plugin message the event after its "ack".
  request(message) {
    return new Promise((resolve, reject) => {
      const transaction = this.send(message);
      this.pending.set(transaction, { resolve, reject });
    });
  }

  message(body, jsep) {
    return this.request({ janus: 'message', session_id: this.session, handle_id: this.handle, body,
                          ...(jsep ? { jsep } : {}) });
  }

  onMessage(m) {
    const waiting = this.pending.get(m.transaction);
    if (m.janus === 'ack' || !waiting) {
      if (m.janus === 'hangup') this.fail('the broadcast server hung up');
      return;
    }
    this.pending.delete(m.transaction);
    if (m.janus === 'error') waiting.reject(new Error(m.error?.reason ?? 'refused'));
    else waiting.resolve(m);
  }

  fail(reason) {
    if (this.closed) return;
    this.close();
    this.onState('lost', reason);
  }

  close() {
    this.closed = true;
    clearInterval(this.keepalive);
    this.ice?.stop();
    if (this.session) this.send({ janus: 'destroy', session_id: this.session });
    this.socket?.close();
    this.pc?.close();
  }
}
