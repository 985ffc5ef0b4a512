// SPDX-License-Identifier: LGPL-2.1-or-later
// The WebRTC side: signalling over the session's WebSocket, the video, and
// the "frames" data channel that says which parameter version each RTP
// timestamp shows (and, for a scene with water, the surface it shows).

import { watchIce } from './ice_watch.js';

const PING_INTERVAL_MS = 5000;
// From a connected path to the first picture: a second or two, more on a
// loaded server. A path that connects and carries no picture (a codec the
// browser cannot decode, a middlebox that passes the handshake and drops
// the media) would otherwise say "live" over an empty stage for ever.
export const FIRST_FRAME_TIMEOUT_MS = 20000;

export class Stream {
  constructor(session, video, { onState, onFrameVersion, codec = 'the video' }) {
    this.session = session;
    this.codec = codec;
    this.video = video;
    this.onState = onState;
    this.onFrameVersion = onFrameVersion;
    this.versions = new Map();  // rtp timestamp -> { version, level }
    this.closed = false;
  }

  start() {
    const url = new URL(this.session.signal_url, location.href);
    url.protocol = location.protocol === 'https:' ? 'wss:' : 'ws:';
    this.socket = new WebSocket(url);
    this.pc = new RTCPeerConnection({ iceServers: [] });
    this.pc.ontrack = (event) => {
      // Ask for no added playout delay: this stream comes over a short, clean
      // path and is interactive, so the jitter buffer's default padding
      // (over 100 ms for VP8) is latency bought for nothing. The standard
      // name is in milliseconds, Chromium's older hint in seconds.
      if ('jitterBufferTarget' in event.receiver) event.receiver.jitterBufferTarget = 0;
      else if ('playoutDelayHint' in event.receiver) event.receiver.playoutDelayHint = 0;
      this.video.srcObject = event.streams[0] ?? new MediaStream([event.track]);
      this.video.play().catch(() => {});
      this.watchFrames();
    };
    this.pc.ondatachannel = ({ channel }) => {
      channel.onmessage = ({ data }) => {
        const { rtp_timestamp: rtp, version, level, water } = JSON.parse(data);
        this.versions.set(rtp, { version, level, water });
        if (this.versions.size > 512) this.versions.delete(this.versions.keys().next().value);
      };
    };
    this.pc.onicecandidate = ({ candidate }) => {
      if (candidate) this.send({ type: 'ice', candidate: candidate.candidate, sdpMLineIndex: candidate.sdpMLineIndex });
    };
    // Chromium says "disconnected" when a path stops answering (a dead
    // server, a dropped network): soon enough to try again at once.
    this.ice = watchIce(this.pc, { onLive: () => this.onLive(), onFail: (why) => this.fail(why),
                                   failOn: ['failed', 'disconnected'] });
    // An offer the browser cannot take would otherwise leave the page
    // "connecting" for ever: it fails the stream, which is tried again.
    this.socket.onmessage = (event) => {
      this.onSignal(event.data).catch((error) => this.fail(`the video could not be set up: ${error.message}`));
    };
    // The server ends a session whose viewer shows no sign of life; the
    // video's RTCP reports usually suffice, this covers the time before.
    this.socket.onopen = () => {
      this.pinger = setInterval(() => this.send({ type: 'ping' }), PING_INTERVAL_MS);
    };
    this.socket.onclose = () => {
      this.socketClosed = true;  // the server ends a session whose signalling closes
      this.fail('the signalling connection closed');
    };
  }

  // Live, and the first picture is due. Counted by what arrived rather
  // than what was drawn: a page in a background tab draws nothing.
  onLive() {
    this.onState('live');
    if (this.firstFrameTimer !== undefined) return;
    this.firstFrameTimer = setTimeout(async () => {
      if (this.closed || await this.framesReceived() > 0) return;
      this.fail(`connected, but no picture came: this browser may not decode ${this.codec} (try the other codec)`);
    }, FIRST_FRAME_TIMEOUT_MS);
  }

  async framesReceived() {
    let frames = 0;
    (await this.pc.getStats()).forEach((r) => {
      if (r.type === 'inbound-rtp' && r.kind === 'video') frames += (r.framesReceived ?? 0) + (r.framesDecoded ?? 0);
    });
    return frames;
  }

  send(message) {
    if (this.socket.readyState === WebSocket.OPEN) this.socket.send(JSON.stringify(message));
  }

  async onSignal(data) {
    const message = JSON.parse(data);
    if (message.type === 'offer') {
      await this.pc.setRemoteDescription({ type: 'offer', sdp: message.sdp });
      const answer = await this.pc.createAnswer();
      await this.pc.setLocalDescription(answer);
      this.send({ type: 'answer', sdp: answer.sdp });
      this.ice.arm();
    } else if (message.type === 'ice' && message.candidate) {
      // One candidate the browser cannot use leaves the others (and ICE's own timeout).
      await this.pc.addIceCandidate({ candidate: message.candidate, sdpMLineIndex: message.sdpMLineIndex })
        .catch((error) => console.warn('ICE candidate not taken:', error.message));
    } else if (message.type === 'bye') {
      this.fail(message.reason);
    }
  }

  // Reports the version (and the water) of every frame the page composites.
  watchFrames() {
    if (!('requestVideoFrameCallback' in this.video)) return;
    const onFrame = (now, meta) => {
      if (this.closed) return;
      const frame = this.versions.get(meta.rtpTimestamp);
      if (frame !== undefined) this.onFrameVersion(frame.version, now, frame.level, frame.water);
      this.video.requestVideoFrameCallback(onFrame);
    };
    this.video.requestVideoFrameCallback(onFrame);
  }

  // The viewer closes the stream once it has let the server know (a DELETE
  // before the socket closes, so that it is not refused).
  fail(reason) {
    if (this.closed) return;
    this.mute();
    this.onState('lost', reason);
  }

  /// No more calls to onState or onFrameVersion: the viewer has moved on.
  mute() { this.closed = true; }

  close() {
    this.closed = true;
    clearInterval(this.pinger);
    clearTimeout(this.firstFrameTimer);
    this.ice?.stop();
    this.socket?.close();
    this.pc?.close();
  }
}
