using System;
using System.Collections.Generic;
using Newtonsoft.Json.Linq;
using Toyroom.Gateway;
using Toyroom.Protocol;
using Toyroom.Transport;

namespace Toyroom.Engine
{
    /// <summary>
    /// Makes an <see cref="IEngine"/> a toyroom engine: serves <c>engine/info</c> (the handshake)
    /// and <c>engine/control</c> (reset, step, pause, resume), takes robot commands, and
    /// publishes each tick's events, statuses and state, in that order, before the state.
    /// Network threads only post work; <see cref="Pump"/> does it, on the caller's thread, so
    /// a Unity scene calls it from <c>FixedUpdate</c>. A <c>step n</c> is answered only after
    /// the engine has run its n ticks (several Pump calls if the game paces them).
    /// </summary>
    public sealed class EngineHost
    {
        private sealed class StepJob
        {
            public long Qid;
            public long Left;
            public readonly List<Event> Events = new List<Event>();
            public readonly List<CommandStatus> Statuses = new List<CommandStatus>();
        }

        private readonly IEngine engine;
        private readonly GatewayClient gateway;
        private readonly MainThreadQueue main = new MainThreadQueue();
        private readonly Queue<StepJob> steps = new Queue<StepJob>();
        private bool paused;

        /// <summary>Log lines (refused frames, dropped messages); defaults to the console.</summary>
        public Action<string> Log = Console.Error.WriteLine;

        /// <summary>Ticks run since start.</summary>
        public long Ticks { get; private set; }

        public EngineHost(IEngine engine, GatewayClient gateway)
        {
            this.engine = engine;
            this.gateway = gateway;
        }

        /// <summary>Serve the engine's keys (call once, after <see cref="GatewayClient.Connect"/>).</summary>
        public void Start()
        {
            gateway.Refused += error => Log("gateway refused a frame: " + error.Code + ": " + error.Message);
            gateway.Serve("engine/info", query => main.Post(() => Info(query)));
            gateway.Serve("engine/control", query => main.Post(() => Control(query)));
            gateway.Subscribe("robot/*/command", sample => main.Post(() => Command(sample)));
        }

        /// <summary>
        /// Do what the network asked for: answer handshakes and control requests, take
        /// commands, and run up to <paramref name="maxTicks"/> ticks of pending steps.
        /// </summary>
        /// <returns>how many ticks ran.</returns>
        public int Pump(int maxTicks = int.MaxValue)
        {
            try
            {
                gateway.Hold(); // each tick's frames go out as one message
                return RunTicks(maxTicks);
            }
            finally
            {
                gateway.Flush();
            }
        }

        private int RunTicks(int maxTicks)
        {
            main.RunPending();
            gateway.Flush();
            gateway.Hold();
            var ran = 0;
            while (steps.Count > 0 && ran < maxTicks)
            {
                var job = steps.Peek();
                var result = engine.Tick();
                ran++;
                Ticks++;
                Publish(result.Events, result.Statuses, result.State);
                job.Events.AddRange(result.Events);
                job.Statuses.AddRange(result.Statuses);
                if (--job.Left > 0)
                {
                    gateway.Flush();
                    gateway.Hold();
                    continue;
                }
                steps.Dequeue();
                gateway.Reply(job.Qid, ControlReplyOf(result.State, job.Events, job.Statuses), true);
                gateway.Flush();
                gateway.Hold();
                main.RunPending(); // commands that arrived during the step act on the next tick
            }
            return ran;
        }

        /// <summary>Block until there is work or <paramref name="timeout"/> passes (for console engines).</summary>
        public bool Wait(TimeSpan timeout)
        {
            return steps.Count > 0 || main.Wait(timeout);
        }

        private void Publish(List<Event> events, List<CommandStatus> statuses, State state)
        {
            foreach (var e in events) gateway.Put("engine/events", e);
            PublishStatuses(statuses);
            gateway.Put("engine/state", state);
        }

        private void PublishStatuses(List<CommandStatus> statuses)
        {
            foreach (var s in statuses) gateway.Put("robot/" + s.Robot + "/status", s);
        }

        private ControlReply ControlReplyOf(State state, List<Event> events, List<CommandStatus> statuses)
        {
            return new ControlReply
            {
                Episode = state.Episode,
                Tick = state.Tick,
                Time = state.Time,
                Paused = paused,
                State = state,
                Events = events,
                Statuses = statuses,
            };
        }

        private void Refuse(long qid, string code, string message)
        {
            gateway.Reply(qid, new ErrorReply { Code = code, Message = message }, false);
        }

        private void Info(Query query)
        {
            var payload = query.Payload as JObject;
            if (payload != null && !ToyroomJson.SameMajor((string)payload["protocol"]))
            {
                Refuse(query.Qid, ErrorCode.VersionMismatch,
                    "this engine speaks " + Protocol.Version.Protocol + ", the client " + payload["protocol"]);
                return;
            }
            var info = engine.Describe();
            if (gateway.Welcome != null) info.World = gateway.Welcome.World;
            gateway.Reply(query.Qid, info, true);
        }

        private void Control(Query query)
        {
            var request = query.Payload as JObject;
            var kind = request == null ? null : (string)request["type"];
            if (request != null && !ToyroomJson.SameMajor((string)request["protocol"]))
            {
                Refuse(query.Qid, ErrorCode.VersionMismatch, "this engine speaks " + Protocol.Version.Protocol);
                return;
            }
            switch (kind)
            {
                case Reset.Tag:
                    State first;
                    try
                    {
                        first = engine.Reset((string)request["scenario"], (long?)request["seed"] ?? 0);
                    }
                    catch (UnknownScenario error)
                    {
                        Refuse(query.Qid, ErrorCode.UnknownScenario, error.Message);
                        return;
                    }
                    steps.Clear();
                    Publish(new List<Event>(), new List<CommandStatus>(), first);
                    gateway.Reply(query.Qid, ControlReplyOf(first, new List<Event>(), new List<CommandStatus>()), true);
                    return;
                case Step.Tag:
                    var n = request["n"];
                    if (n == null || n.Type != JTokenType.Integer || (long)n < 1 || (long)n > 1000000)
                    {
                        Refuse(query.Qid, ErrorCode.BadRequest, "step: n must be an integer in [1, 1000000], got " + n);
                        return;
                    }
                    steps.Enqueue(new StepJob { Qid = query.Qid, Left = (long)n });
                    return;
                case Pause.Tag:
                case Resume.Tag:
                    paused = kind == Pause.Tag; // lock-step: only reported
                    gateway.Reply(query.Qid,
                        ControlReplyOf(engine.Current, new List<Event>(), new List<CommandStatus>()), true);
                    return;
                default:
                    Refuse(query.Qid, ErrorCode.BadRequest,
                        "engine/control takes reset, step, pause or resume, got " + (kind ?? "no type"));
                    return;
            }
        }

        private void Command(Sample sample)
        {
            RobotCommand command;
            try
            {
                command = ToyroomJson.Read<RobotCommand>(sample.Payload);
            }
            catch (Exception error)
            {
                Log("dropped a message on " + sample.Key + ": " + error.Message);
                return;
            }
            if (command == null || command.Type != RobotCommand.Tag || command.Action == null)
            {
                Log("dropped a message on " + sample.Key + ": not a robot_command");
                return;
            }
            PublishStatuses(engine.Command(command));
        }
    }
}
