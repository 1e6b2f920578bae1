// A ground station built on ArduPilot's node-mavlink (an implementation independent of ours, with its own CRC_EXTRA
// table generated from the official XML) flying `uascma sitl`. Usage: node interop.mjs PORT MISSION.plan
// Checks: every frame from the vehicle parses (checksum) and its sequence numbers run without a gap; the mission
// file uploads (MISSION_COUNT → MISSION_REQUEST_INT → MISSION_ITEM_INT … → MISSION_ACK) and downloads back equal;
// ARM and MISSION_START are acknowledged; the telemetry comes once per simulated second (SYSTEM_TIME's clock); the
// CMA's STATUSTEXT and the landing are seen. Prints "N passed, N failed"; exit status 1 on any failure.
import dgram from 'node:dgram'
import { readFileSync } from 'node:fs'
import { MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, minimal, common,
         registerCustomMessageMagicNumber } from 'node-mavlink'

const [port, missionPath, mode] = [Number(process.argv[2]), process.argv[3], process.argv[4] || 'start']
const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY }
// node-mavlink's tables (mavlink-mappings 1.0.21) stop at id 255 in common: ESC_INFO and ESC_STATUS get their
// published CRC_EXTRA (251, 10), so that their checksums are checked too.
registerCustomMessageMagicNumber('290', 251)
registerCustomMessageMagicNumber('291', 10)
const ID = { HEARTBEAT: 0, SYSTEM_TIME: 2, MISSION_REQUEST_INT: 51, MISSION_COUNT: 44, MISSION_ITEM_INT: 73,
             MISSION_ACK: 47, COMMAND_ACK: 77, STATUSTEXT: 253, EXTENDED_SYS_STATE: 245, BATTERY_STATUS: 147,
             GLOBAL_POSITION_INT: 33, MISSION_ITEM_REACHED: 46 }
const results = []
const check = (ok, what) => { results.push(ok); console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`) }

const socket = dgram.createSocket('udp4')
const splitter = new MavLinkPacketSplitter()
const reader = splitter.pipe(new MavLinkPacketParser())
const protocol = new MavLinkProtocolV2(255, 190)
let sequence = 0
const send = (message) => socket.send(protocol.serialize(message, sequence++ % 256), port, '127.0.0.1')
socket.on('message', (datagram) => splitter.write(datagram))

const counts = {}
const texts = []
const reached = []
let lastSeq = null
let sequenceGaps = 0
let firstTime = null, lastTime = null, heartbeatsInFlight = 0, started = false, firstFlightTime = null
let airborneSeen = false, landedAfterAirborne = false, ended = false
let waiters = []
reader.on('data', (packet) => {
  const { msgid, seq, sysid } = packet.header
  if (sysid !== 1) return
  if (lastSeq !== null && seq !== (lastSeq + 1) % 256) sequenceGaps++
  lastSeq = seq
  counts[msgid] = (counts[msgid] || 0) + 1
  const clazz = REGISTRY[msgid]
  if (!clazz) return
  const data = packet.protocol.data(packet.payload, clazz)
  if (msgid === ID.MISSION_ITEM_REACHED) reached.push(data.seq)
  if (msgid === ID.STATUSTEXT) {
    texts.push(data.text)
    if (/^(completed|emergency_landing|terminated|failed|landed|timeout|grounded)/.test(data.text)) ended = true
  }
  if (msgid === ID.SYSTEM_TIME && started && !ended) {
    if (firstTime === null) firstTime = data.timeBootMs
    lastTime = data.timeBootMs
  }
  if (msgid === ID.HEARTBEAT && started && !ended) heartbeatsInFlight++
  if (msgid === ID.EXTENDED_SYS_STATE) {
    if (data.landedState === 2) airborneSeen = true
    if (airborneSeen && data.landedState === 1) landedAfterAirborne = true
  }
  waiters = waiters.filter((w) => !(w.msgid === msgid && w.accept(data) && (w.resolve(data), true)))
})
const waitFor = (msgid, accept = () => true, timeoutMs = 5000) => new Promise((resolve, reject) => {
  const timer = setTimeout(() => reject(new Error(`no message ${msgid} within ${timeoutMs} ms`)), timeoutMs)
  waiters.push({ msgid, accept, resolve: (data) => { clearTimeout(timer); resolve(data) } })
})

function missionItems(path) {
  const plan = JSON.parse(readFileSync(path, 'utf8'))
  return plan.mission.items.filter((item) => item.type === 'SimpleItem').map((item, seq) => {
    const message = new common.MissionItemInt()
    const p = item.params.map((v) => (v === null ? NaN : v))
    Object.assign(message, { targetSystem: 1, targetComponent: 1, seq, frame: item.frame, command: item.command,
      current: seq === 0 ? 1 : 0, autocontinue: item.autoContinue ? 1 : 0, param1: p[0], param2: p[1], param3: p[2],
      param4: p[3], x: Math.round(p[4] * 1e7), y: Math.round(p[5] * 1e7), z: p[6], missionType: 0 })
    return message
  })
}

// MISSION_COUNT, each requested MISSION_ITEM_INT; resolves to the MISSION_ACK.
async function upload(items) {
  const count = new common.MissionCount()
  Object.assign(count, { targetSystem: 1, targetComponent: 1, count: items.length, missionType: 0 })
  const acked = waitFor(ID.MISSION_ACK, () => true, 10000)
  for (let seq = 0; seq < items.length; seq++) {
    const asked = waitFor(ID.MISSION_REQUEST_INT, (r) => r.seq === seq)
    if (seq === 0) send(count)
    await asked
    send(items[seq])
  }
  return acked
}

// COMMAND_LONG; resolves to its COMMAND_ACK.
function command(id, param1) {
  const message = new common.CommandLong()
  Object.assign(message, { targetSystem: 1, targetComponent: 1, command: id, confirmation: 0, _param1: param1 })
  const answer = waitFor(ID.COMMAND_ACK, (a) => a.command === id)
  send(message)
  return answer
}

const same = (a, b) => (Number.isNaN(a) && Number.isNaN(b)) || Math.fround(a) === Math.fround(b)

async function main() {
  const heartbeat = new minimal.Heartbeat()
  Object.assign(heartbeat, { type: 6, autopilot: 8, baseMode: 0, customMode: 0, systemStatus: 4, mavlinkVersion: 3 })
  send(heartbeat)
  const vehicle = await waitFor(ID.HEARTBEAT)
  check(vehicle.type === 13, 'HEARTBEAT from a hexarotor (MAV_TYPE 13)')
  const items = missionItems(missionPath)
  if (mode === 'mission') {
    check((await command(400, 1)).result === 0, 'ARM before any upload: MAV_RESULT_ACCEPTED')
    const denial = waitFor(ID.STATUSTEXT, (t) => /^start denied: no mission/.test(t.text))
    check((await command(300, 0)).result === 2, 'MISSION_START with no mission: MAV_RESULT_DENIED')
    await denial
    const refusal = waitFor(ID.STATUSTEXT, (t) => /^mission refused/.test(t.text))
    const unflyable = items.slice()
    const loiter = Object.assign(new common.MissionItemInt(), items[1], { command: 17 })
    unflyable.splice(1, 0, loiter)
    unflyable.forEach((item, seq) => { unflyable[seq] = Object.assign(new common.MissionItemInt(), item, { seq }) })
    check((await upload(unflyable)).type !== 0, 'an upload with NAV_LOITER_UNLIM: MISSION_ACK with an error type')
    const why = await refusal
    check(/LOITER_UNLIM|never ends/.test(texts.join('')), `STATUSTEXT naming why: "${why.text}…"`)
  }
  const acked = upload(items)
  check((await acked).type === 0, `upload of ${items.length} items accepted`)
  // Download, compared item by item.
  const list = new common.MissionRequestList()
  Object.assign(list, { targetSystem: 1, targetComponent: 1, missionType: 0 })
  const listed = waitFor(ID.MISSION_COUNT)
  send(list)
  check((await listed).count === items.length, 'download: the same count')
  let equal = true
  for (let seq = 0; seq < items.length; seq++) {
    const request = new common.MissionRequestInt()
    Object.assign(request, { targetSystem: 1, targetComponent: 1, seq, missionType: 0 })
    const got = waitFor(ID.MISSION_ITEM_INT, (i) => i.seq === seq)
    send(request)
    const item = await got
    const sent = items[seq]
    for (const field of ['frame', 'command', 'autocontinue', 'x', 'y']) equal = equal && item[field] === sent[field]
    for (const field of ['param1', 'param2', 'param3', 'param4', 'z']) equal = equal && same(item[field], sent[field])
  }
  check(equal, 'download: every item equal to the uploaded one')
  const ack = new common.MissionAck()
  Object.assign(ack, { targetSystem: 1, targetComponent: 1, type: 0, missionType: 0 })
  send(ack)
  // Commands.
  for (const [id, param1, what] of [[400, 1, 'ARM'], [300, 0, 'MISSION_START']]) {
    if (id === 300) started = true
    check((await command(id, param1)).result === 0, `${what} acknowledged MAV_RESULT_ACCEPTED`)
  }
  // The rest of the flight.
  await waitFor(ID.STATUSTEXT, (t) => /^(completed|emergency_landing|terminated|failed|landed)/.test(t.text), 120000)
    .catch(() => {})
  await new Promise((resolve) => setTimeout(resolve, 1000))
  socket.close()
  check(splitter.invalidPackages === 0 && splitter.unknownPackagesCount === 0,
        `every frame's checksum valid (${splitter.validPackages} valid, ${splitter.invalidPackages} invalid)`)
  check(sequenceGaps === 0, `no sequence gap (${sequenceGaps})`)
  const simulatedS = (lastTime - firstTime) / 1000
  const rate = heartbeatsInFlight / simulatedS
  check(Math.abs(rate - 1) < 0.05, `HEARTBEAT ${rate.toFixed(3)} per simulated second over ${simulatedS} s`)
  check(counts[ID.BATTERY_STATUS] === 2 * counts[ID.HEARTBEAT], 'two BATTERY_STATUS (one per pack) per HEARTBEAT')
  check(counts[ID.GLOBAL_POSITION_INT] === counts[ID.HEARTBEAT], 'GLOBAL_POSITION_INT with every HEARTBEAT')
  const events = mode === 'mission'
    ? [[/^completed/, 'the mission completed']]
    : [[/^spall/, 'the spall'], [/jammed/, 'the jam'], [/isolated/, 'the isolation'],
       [/^(LandPract|LandASAP)/, "the CMA's action"], [/^emergency_landing|^completed/, 'the landing']]
  for (const [pattern, what] of events) check(texts.some((t) => pattern.test(t)), `STATUSTEXT: ${what}`)
  if (mode === 'mission') {
    // Every item that moves the vehicle (NAV_* of the common set: 16-99), in the mission's order.
    const moving = items.filter((item) => item.command >= 16 && item.command < 100).map((item) => item.seq)
    check(JSON.stringify(reached) === JSON.stringify(moving),
          `MISSION_ITEM_REACHED ${JSON.stringify(reached)}, the moving items ${JSON.stringify(moving)}`)
  }
  console.log(`STATUSTEXT seen: ${JSON.stringify(texts)}`)
  check(landedAfterAirborne, 'EXTENDED_SYS_STATE: in the air, then on the ground')
  const failed = results.filter((ok) => !ok).length
  console.log(`${results.length - failed} passed, ${failed} failed`)
  process.exit(failed === 0 ? 0 : 1)
}

main().catch((error) => {
  console.log(`FAIL ${error.message}`)
  console.log(`${results.filter((ok) => ok).length} passed, ${results.filter((ok) => !ok).length + 1} failed`)
  process.exit(1)
})
