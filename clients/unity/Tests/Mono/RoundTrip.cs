using System;
using System.IO;
using Newtonsoft.Json.Linq;
using Toyroom.Protocol;

namespace Toyroom.Tests
{
    /// <summary>
    /// <c>mono RoundTrip.exe EXAMPLES_DIR OUT_DIR</c>: reads every golden example
    /// (protocol/examples/TYPE.json) into its generated class and writes it back to OUT_DIR, so
    /// the Python side can check that nothing was lost or changed. Exit 1 on the first failure.
    /// </summary>
    public static class RoundTrip
    {
        public static int Main(string[] args)
        {
            var types = new System.Collections.Generic.Dictionary<string, Type>
            {
                { "hello", typeof(Hello) }, { "engine_info", typeof(EngineInfo) }, { "reset", typeof(Reset) },
                { "step", typeof(Step) }, { "pause", typeof(Pause) }, { "resume", typeof(Resume) },
                { "control_reply", typeof(ControlReply) }, { "error", typeof(ErrorReply) },
                { "state", typeof(State) }, { "event", typeof(Event) }, { "truth", typeof(Truth) },
                { "robot_command", typeof(RobotCommand) }, { "command_status", typeof(CommandStatus) },
                { "heartbeat", typeof(Heartbeat) }, { "mind", typeof(Mind) },
                { "person_command", typeof(PersonCommand) },
            };
            Directory.CreateDirectory(args[1]);
            foreach (var path in Directory.GetFiles(args[0], "*.json"))
            {
                var tag = Path.GetFileNameWithoutExtension(path);
                Type type;
                if (!types.TryGetValue(tag, out type))
                {
                    Console.Error.WriteLine("no C# class for example " + tag);
                    return 1;
                }
                var message = JToken.Parse(File.ReadAllText(path)).ToObject(type, ToyroomJson.Serializer);
                File.WriteAllText(Path.Combine(args[1], tag + ".json"), ToyroomJson.Write(message));
            }
            var unknown = JObject.Parse("{\"type\":\"robot_command\",\"protocol\":\"1.1\",\"id\":\"c1\","
                + "\"robot\":\"robot\",\"action\":{\"kind\":\"teleport\",\"to\":\"S1\"}}");
            var kept = unknown.ToObject<RobotCommand>(ToyroomJson.Serializer);
            if (!(kept.Action is UnknownAction) || kept.Action.Kind != "teleport")
            {
                Console.Error.WriteLine("an unknown action kind was not kept: " + kept.Action);
                return 1;
            }
            File.WriteAllText(Path.Combine(args[1], "unknown_action.json"), ToyroomJson.Write(kept));
            Console.WriteLine("round trip: " + types.Count + " message types");
            return 0;
        }
    }
}
