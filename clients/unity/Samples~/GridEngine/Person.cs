using System.Collections.Generic;
using Newtonsoft.Json.Linq;

namespace Toyroom.Samples.GridEngine
{
    /// <summary>A scripted person: its route (the scenario's steps), and where it is in it.</summary>
    public sealed class Person
    {
        public readonly string Id;
        public readonly string Wants;
        public readonly bool Answers;
        public List<JObject> Plan;
        public int Index;
        public bool Started;
        public int Left;

        public Person(JObject spec, ScenarioFile scenario, double tickSeconds)
        {
            Id = (string)spec["id"];
            Wants = (string)spec["wants"];
            Answers = (bool?)spec["answers"] ?? false;
            Plan = new List<JObject>();
            foreach (JObject step in (JArray)spec["script"])
            {
                var copy = (JObject)step.DeepClone();
                if (copy["ticks"] != null) copy["ticks"] = scenario.Scaled((int)copy["ticks"], tickSeconds);
                Plan.Add(copy);
            }
        }

        public JObject Step { get { return Plan[Index]; } }

        /// <summary>Done with the script, or playing, using or waiting with no end.</summary>
        public bool Finished
        {
            get
            {
                if (Index >= Plan.Count) return true;
                var step = Plan[Index];
                var open = (string)step["do"] == "play" || (string)step["do"] == "use" || (string)step["do"] == "wait";
                return Started && open && step["ticks"] == null && step["until"] == null;
            }
        }

        public void Replace(params JObject[] plan)
        {
            Plan = new List<JObject>(plan);
            Index = 0;
            Started = false;
        }

        public static JObject Do(string what, params string[] fields)
        {
            var step = new JObject { ["do"] = what };
            for (var i = 0; i + 1 < fields.Length; i += 2) step[fields[i]] = fields[i + 1];
            return step;
        }
    }
}
